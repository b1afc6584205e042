#include "systems/dem/pair_kernel.hpp"

#include <cmath>

#include "systems/dem/nearest_image.hpp"

namespace granflow::dem {

namespace {

enum class Law { uniform_lsd, lsd, hertz };

// Every pair is evaluated as if in contact and the result selected by the
// overlap: a branch on it would be mispredicted for a third of the pairs of
// a dense bed, and the selection lets the loop be vectorised.
// With one radius (same_radius) every pair has the same reach, and two
// gathers per pair fewer.
template <int D, Law law_kind, bool same_radius>
PairTotals sweep_pairs(const PairSweep<D>& s, std::size_t begin, std::size_t end) {
  const double* const x = s.x;
  const double* const v = s.v;
  const double* const radius = s.radius;
  const double* const mass = s.mass;
  const std::uint32_t* const first = s.first;
  const std::uint32_t* const second = s.second;
  const ContactLaw law = s.law;
  const double uniform_gamma = law_kind == Law::uniform_lsd ? law.gamma(0.5 * mass[0]) : 0.0;
  double* const force = s.force;
  double length[D], half[D];
  for (int a = 0; a < D; ++a) {
    length[a] = s.length[a];
    half[a] = s.half[a];
  }
  double elastic = 0.0, dissipated = 0.0, contacts = 0.0;
#pragma omp simd reduction(+ : elastic, dissipated, contacts)
  for (std::size_t p = begin; p < end; ++p) {
    const std::size_t i = first[p], j = second[p];
    double d[D], d2 = 0.0, closing = 0.0;
    for (int a = 0; a < D; ++a) {
      d[a] = nearest_image(x[i * D + a] - x[j * D + a], length[a], half[a]);
      d2 += d[a] * d[a];
      closing += (v[i * D + a] - v[j * D + a]) * d[a];
    }
    const double reach = same_radius ? 2.0 * radius[0] : radius[i] + radius[j];
    const bool touching = d2 < reach * reach;
    const double distance = std::sqrt(d2), inverse = 1.0 / distance;
    const double delta = reach - distance, rate = -closing * inverse;
    ContactLaw::Result r;
    if constexpr (law_kind == Law::uniform_lsd) {
      r = law.lsd(delta, rate, uniform_gamma);
    } else if constexpr (law_kind == Law::lsd) {
      r = law.lsd(delta, rate, law.gamma(mass[i] * mass[j] / (mass[i] + mass[j])));
    } else {
      r = law.hertz(touching ? delta : 0.0, rate);
    }
    const double magnitude = touching ? r.force * inverse : 0.0;
    for (int a = 0; a < D; ++a) force[(p - begin) * D + a] = magnitude * d[a];
    // Weighted rather than selected: GCC 12 vectorises a selected sum under
    // the simd pragma with -march=native into wrong totals
    // (tests/systems/dem/pair_kernel_test.cpp).
    const double weight = touching ? 1.0 : 0.0;
    elastic += weight * r.elastic;
    dissipated += weight * r.dissipated;
    contacts += weight;
  }
  return {elastic, dissipated, contacts};
}

}  // namespace

template <int D>
PairTotals normal_pair_forces(const PairSweep<D>& sweep, std::size_t begin, std::size_t end) {
  const bool one_radius = sweep.same_radius;
  if (sweep.law.model == ContactModel::hertz)
    return one_radius ? sweep_pairs<D, Law::hertz, true>(sweep, begin, end)
                      : sweep_pairs<D, Law::hertz, false>(sweep, begin, end);
  if (sweep.uniform_mass)
    return one_radius ? sweep_pairs<D, Law::uniform_lsd, true>(sweep, begin, end)
                      : sweep_pairs<D, Law::uniform_lsd, false>(sweep, begin, end);
  return one_radius ? sweep_pairs<D, Law::lsd, true>(sweep, begin, end) : sweep_pairs<D, Law::lsd, false>(sweep, begin, end);
}

template PairTotals normal_pair_forces<2>(const PairSweep<2>&, std::size_t, std::size_t);
template PairTotals normal_pair_forces<3>(const PairSweep<3>&, std::size_t, std::size_t);

}  // namespace granflow::dem
