#pragma once
// The normal forces of a range of frictionless sphere pairs, compiled in its
// own translation unit (systems/dem/pair_kernel.cpp) with the flags that let
// the compiler turn the loop into vector code: one branch-free pass over the
// pairs of the half neighbour lists, the pair's two spheres gathered by
// index, the force stored per pair (D doubles, from force[0] for the
// range's first pair). Out of contact a pair's force is zero. Each pair's force
// is the same whatever the vector width; the energy sums of a range are
// added in an order that depends on it, never on the thread count.

#include <cstddef>
#include <cstdint>

#include "systems/dem/contact_law.hpp"

namespace granflow::dem {

template <int D>
struct PairSweep {
  const double* x = nullptr;  // D per sphere
  const double* v = nullptr;
  const double* radius = nullptr;
  const double* mass = nullptr;
  const std::uint32_t* first = nullptr;  // per pair
  const std::uint32_t* second = nullptr;
  double length[D] = {};  // the box
  double half[D] = {};    // half its length along periodic axes, infinity along the others (nearest_image)
  ContactLaw law;
  bool uniform_mass = false;  // every sphere has mass[0]: one reduced mass for all pairs
  bool same_radius = false;   // every sphere has radius[0]
  double* force = nullptr;    // D per pair of the range: the force on the first sphere
};

struct PairTotals {
  double elastic = 0.0;
  double dissipated = 0.0;
  double contacts = 0.0;
};

// Pairs [begin, end).
template <int D>
PairTotals normal_pair_forces(const PairSweep<D>& sweep, std::size_t begin, std::size_t end);

}  // namespace granflow::dem
