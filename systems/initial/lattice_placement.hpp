#pragma once
// Non-overlapping positions at any packing fraction a hard-sphere fluid can
// have, where random sequential addition cannot go (it jams at 0.384 in 3D
// and 0.547 in 2D): sites of a face-centred cubic lattice (3D) or a centred
// square lattice (2D), the cubic sites whose coordinate indices sum to an
// even number, spread evenly over the box with randomly chosen vacancies.
// An elastic event-driven run then melts the lattice into an equilibrium
// fluid (Alder & Wainwright 1957 started their hard-sphere runs the same way);
// hard spheres stay fluid up to a packing fraction of 0.494 (Hoover & Ree
// 1968), hard disks up to about 0.70.
//
// Along a periodic axis the n sites of a row sit at (k + 1/2) L / n with n
// even, so the lattice closes on itself across the boundary; along a wall
// axis they span [r, L - r], touching neither wall.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "components/box.hpp"
#include "components/vector.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "systems/initial/random_placement.hpp"

namespace granflow {

namespace detail {

// Sites per axis of the cubic grid (every other one is used), and the spacing
// they give along that axis.
template <int D>
struct LatticeGrid {
  std::array<std::int64_t, D> sites{};
  std::array<double, D> spacing{};

  std::int64_t used_sites() const {
    std::int64_t total = 1;
    for (int a = 0; a < D; ++a) total *= sites[a];
    // Sites of even index sum: half of them, the odd one included when every
    // count is odd.
    return (total + 1) / 2;
  }

  // Closest distance between used sites: two steps along one axis, or one
  // step along each of two axes.
  double closest() const {
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a < D; ++a) {
      if (sites[a] > 2) best = std::min(best, 2.0 * spacing[a]);
      for (int b = a + 1; b < D; ++b)
        if (sites[a] > 1 && sites[b] > 1) best = std::min(best, std::hypot(spacing[a], spacing[b]));
    }
    return best;
  }
};

template <int D>
LatticeGrid<D> lattice_grid(const Box<D>& box, double radius, const std::array<std::int64_t, D>& sites) {
  LatticeGrid<D> grid;
  grid.sites = sites;
  for (int a = 0; a < D; ++a) {
    const double extent = box.periodic[a] ? box.length[a] : box.length[a] - 2.0 * radius;
    const auto n = static_cast<double>(sites[a]);
    grid.spacing[a] = box.periodic[a] ? box.length[a] / n : (sites[a] > 1 ? extent / (n - 1) : extent);
  }
  return grid;
}

// The grid of about `scale` spacing: even counts along periodic axes.
template <int D>
LatticeGrid<D> lattice_grid(const Box<D>& box, double radius, double scale) {
  std::array<std::int64_t, D> sites{};
  for (int a = 0; a < D; ++a) {
    const double extent = box.periodic[a] ? box.length[a] : box.length[a] - 2.0 * radius;
    auto n = static_cast<std::int64_t>(std::ceil(extent / scale));
    sites[a] = box.periodic[a] ? std::max<std::int64_t>(2, n + n % 2) : std::max<std::int64_t>(1, n + 1);
  }
  return lattice_grid<D>(box, radius, sites);
}

}  // namespace detail

// Random vacancies: keeps `count` of the sites, chosen by a partial
// Fisher-Yates shuffle (stream lattice_vacancy of `seed`).
template <int D>
void keep_random_sites(std::vector<Vec<D>>& sites, std::size_t count, std::uint64_t seed) {
  for (std::size_t k = 0; k < count; ++k) {
    Philox random(stream::lattice_vacancy, seed, 0, k);
    const auto pick = k + static_cast<std::size_t>(random.uniform() * static_cast<double>(sites.size() - k));
    std::swap(sites[k], sites[std::min(pick, sites.size() - 1)]);
  }
  sites.resize(count);
}

// Centres of `count` spheres (disks) of at most `radius` on a lattice filling
// `box`, `count` of its sites chosen at random (stream lattice_vacancy of
// `seed`). The lattice is the coarsest that offers `count` sites, so its
// closest sites are as far apart as the box allows.
template <int D>
struct LatticePlacement {
  std::vector<Vec<D>> positions;
  // Where the lattice has a Bragg peak of height N: pi over the spacing
  // along every axis (all used sites have the same phase there).
  Vec<D> bragg_vector;
};

// |sum_i exp(i k.x_i)|^2 / N: of order N on the lattice at its Bragg vector,
// of order 1 in a fluid.
template <int D>
double structure_factor(const std::vector<Vec<D>>& positions, const Vec<D>& k) {
  double re = 0.0, im = 0.0;
  for (const auto& x : positions) {
    const double phase = k.dot(x);
    re += std::cos(phase);
    im += std::sin(phase);
  }
  return positions.empty() ? 0.0 : (re * re + im * im) / static_cast<double>(positions.size());
}

template <int D>
LatticePlacement<D> place_on_lattice(const Box<D>& box, std::size_t count, double radius, std::uint64_t seed) {
  double volume = 1.0;
  for (int a = 0; a < D; ++a) {
    if (!box.periodic[a] && box.length[a] < 2.0 * radius)
      throw PlacementError(fmt::format("box length {} along axis {} is narrower than a particle of radius {}",
                                       box.length[a], a, radius));
    volume *= box.length[a];
  }
  const double fraction = static_cast<double>(count) * ball_volume<D>(radius) / volume;
  // The grid spacing is bisected between one that gives too few sites and
  // one that gives enough (half the cubic cells per site).
  double coarse = 4.0 * std::pow(2.0 * volume / static_cast<double>(std::max<std::size_t>(count, 1)), 1.0 / D);
  double fine = coarse;
  while (detail::lattice_grid<D>(box, radius, fine).used_sites() < static_cast<std::int64_t>(count)) fine *= 0.5;
  for (int it = 0; it < 60; ++it) {
    const double middle = 0.5 * (coarse + fine);
    (detail::lattice_grid<D>(box, radius, middle).used_sites() >= static_cast<std::int64_t>(count) ? fine : coarse) =
        middle;
  }
  // A box whose shape does not suit `count` (it holds many more sites than
  // that at the same spacing on every axis) gets a few rows fewer along some
  // axes: the counts near the uniform ones that still offer `count` sites and
  // keep the closest sites furthest apart.
  auto grid = detail::lattice_grid<D>(box, radius, fine);
  const auto uniform = grid.sites;
  std::array<int, D> change{};
  while (true) {
    std::array<std::int64_t, D> sites{};
    bool possible = true;
    for (int a = 0; a < D; ++a) {
      const std::int64_t step = box.periodic[a] ? 2 : 1;
      sites[a] = uniform[a] - step * change[a];
      possible = possible && sites[a] >= (box.periodic[a] ? 2 : 1);
    }
    if (possible) {
      const auto candidate = detail::lattice_grid<D>(box, radius, sites);
      if (candidate.used_sites() >= static_cast<std::int64_t>(count) && candidate.closest() > grid.closest())
        grid = candidate;
    }
    int a = 0;
    for (; a < D; ++a) {
      if (++change[a] < 3) break;
      change[a] = 0;
    }
    if (a == D) break;
  }
  if (grid.closest() < 2.0 * radius)
    throw PlacementError(fmt::format("cannot place {} particles of radius {} on a lattice in this box: packing "
                                     "fraction {:.4f} leaves lattice sites {:.6g} apart, closer than a diameter; "
                                     "lower system.count or system.radius",
                                     count, radius, fraction, grid.closest()));
  std::vector<Vec<D>> sites;
  sites.reserve(static_cast<std::size_t>(grid.used_sites()));
  std::array<std::int64_t, D> index{};
  while (true) {
    std::int64_t parity = 0;
    for (int a = 0; a < D; ++a) parity += index[a];
    if (parity % 2 == 0) {
      Vec<D> x;
      for (int a = 0; a < D; ++a)
        x[a] = box.periodic[a] ? (static_cast<double>(index[a]) + 0.5) * grid.spacing[a]
                               : (grid.sites[a] > 1 ? radius + static_cast<double>(index[a]) * grid.spacing[a]
                                                    : 0.5 * box.length[a]);
      sites.push_back(x);
    }
    int a = 0;
    for (; a < D; ++a) {
      if (++index[a] < grid.sites[a]) break;
      index[a] = 0;
    }
    if (a == D) break;
  }
  keep_random_sites<D>(sites, count, seed);
  LatticePlacement<D> placement{std::move(sites), Vec<D>::Zero()};
  for (int a = 0; a < D; ++a) placement.bragg_vector[a] = std::numbers::pi / grid.spacing[a];
  return placement;
}

}  // namespace granflow
