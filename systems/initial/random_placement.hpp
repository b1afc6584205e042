#pragma once
// Random non-overlapping placement by random sequential addition, with a
// hash grid so each trial checks only nearby particles: O(N) for dilute
// systems, fast for 10^6 particles. Random sequential addition jams (at
// packing fraction ~0.384 in 3D, ~0.547 in 2D); requests beyond that are
// refused at once, and requests it cannot reach in practice fail with an
// error that says so instead of looping forever.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "components/box.hpp"
#include "components/vector.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"

#include "engine/core/input_error.hpp"
#include "engine/run/preparation.hpp"
#include "systems/initial/placement_grid.hpp"

namespace granflow {

class PlacementError : public InputError {
 public:
  using InputError::InputError;
};

// Volume (area in 2D) of a sphere (disk) of radius r.
template <int D>
double ball_volume(double r) {
  return D == 3 ? 4.0 / 3.0 * std::numbers::pi * r * r * r : std::numbers::pi * r * r;
}

template <int D>
constexpr double random_sequential_jamming_fraction() {
  return D == 3 ? 0.3841 : 0.5472;
}

// Places particles with the given radii inside `region` of `box`. Along
// periodic axes of the box that the region spans fully, particles may cross
// the boundary; elsewhere they stay inside the region.
template <int D>
std::vector<Vec<D>> place_randomly(const Box<D>& box, const PlacementRegion<D>& region,
                                   const std::vector<double>& radii, std::uint64_t seed,
                                   const Preparation& preparation = {},
                                   std::uint64_t max_attempts_per_particle = 20000) {
  const std::size_t count = radii.size();
  std::vector<Vec<D>> positions(count);
  if (count == 0) return positions;
  const double max_radius = *std::max_element(radii.begin(), radii.end());

  const std::array<bool, D> wraps = wrapping_axes(box, region);
  double region_volume = 1.0;
  for (int a = 0; a < D; ++a) {
    region_volume *= region.upper[a] - region.lower[a];
    if (!wraps[a] && region.upper[a] - region.lower[a] <= 2.0 * max_radius)
      throw PlacementError(fmt::format("placement region along axis {} ({} wide) is narrower than a particle "
                                       "(diameter {}): lower system.radius or enlarge the box",
                                       a, region.upper[a] - region.lower[a], 2.0 * max_radius));
  }
  double occupied = 0.0;
  for (double r : radii) occupied += ball_volume<D>(r);
  const double fraction = occupied / region_volume;
  if (fraction >= random_sequential_jamming_fraction<D>())
    throw PlacementError(fmt::format(
        "cannot place {} particles at packing fraction {:.4f}: random sequential placement jams at {:.3f} in {}D; "
        "lower system.count or system.radius",
        count, fraction, random_sequential_jamming_fraction<D>(), D));

  PlacementGrid<D> grid(box, region, 2.0 * max_radius, count);
  const auto overlaps = [&](const Vec<D>& x, double r) {
    return grid.any_near(x, [&](std::size_t k) {
      Vec<D> dx = positions[k] - x;
      for (int a = 0; a < D; ++a)
        if (wraps[a]) dx[a] -= box.length[a] * std::round(dx[a] / box.length[a]);
      const double contact = r + radii[k];
      return dx.squaredNorm() < contact * contact;
    });
  };

  // Near jamming the last particles take most of the attempts: report often.
  const std::size_t report_every = std::max<std::size_t>(1, count / 1000);
  for (std::size_t i = 0; i < count; ++i) {
    if (i % report_every == 0) {
      preparation.stop_if_interrupted();
      preparation.progress(static_cast<double>(i) / static_cast<double>(count));
    }
    Philox random(stream::placement, seed, 0, i);
    bool placed = false;
    for (std::uint64_t attempt = 0; attempt < max_attempts_per_particle && !placed; ++attempt) {
      Vec<D> x;
      for (int a = 0; a < D; ++a) {
        const double margin = wraps[a] ? 0.0 : radii[i];
        x[a] = region.lower[a] + margin + random.uniform() * (region.upper[a] - region.lower[a] - 2.0 * margin);
      }
      if (overlaps(x, radii[i])) continue;
      positions[i] = x;
      grid.insert(i, x);
      placed = true;
    }
    if (!placed)
      throw PlacementError(fmt::format(
          "random placement failed: no free spot for particle {} of {} after {} attempts (packing fraction "
          "{:.4f}; random sequential placement becomes impractical close to its jamming fraction {:.3f} in {}D)",
          i + 1, count, max_attempts_per_particle, fraction, random_sequential_jamming_fraction<D>(), D));
  }
  return positions;
}

}  // namespace granflow
