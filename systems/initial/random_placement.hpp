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
#include "engine/rng.hpp"
#include "engine/stream_ids.hpp"

#include "engine/input_error.hpp"
#include "engine/preparation.hpp"

namespace granflow {

class PlacementError : public InputError {
 public:
  using InputError::InputError;
};

template <int D>
struct PlacementRegion {
  std::array<double, D> lower{};
  std::array<double, D> upper{};
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

  std::array<bool, D> wraps{};
  double region_volume = 1.0;
  for (int a = 0; a < D; ++a) {
    wraps[a] = box.periodic[a] && region.lower[a] <= 0.0 && region.upper[a] >= box.length[a];
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

  // Hash grid over the region, cells one largest diameter wide.
  std::array<std::int64_t, D> cells{};
  std::array<double, D> width{};
  std::size_t total = 1;
  for (int a = 0; a < D; ++a) {
    const double extent = region.upper[a] - region.lower[a];
    cells[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(extent / (2.0 * max_radius)));
    while (total * static_cast<std::size_t>(cells[a]) > 4 * count + 64 && cells[a] > 1) cells[a] /= 2;
    width[a] = extent / static_cast<double>(cells[a]);
    total *= static_cast<std::size_t>(cells[a]);
  }
  std::vector<std::int64_t> head(total, -1), next(count, -1);
  const auto coordinates = [&](const Vec<D>& x) {
    std::array<std::int64_t, D> c{};
    for (int a = 0; a < D; ++a)
      c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>((x[a] - region.lower[a]) / width[a]), 0, cells[a] - 1);
    return c;
  };
  const auto linear = [&](const std::array<std::int64_t, D>& c) {
    std::size_t k = 0;
    for (int a = D - 1; a >= 0; --a) k = k * static_cast<std::size_t>(cells[a]) + static_cast<std::size_t>(c[a]);
    return k;
  };
  // Neighbour cells reach as far as the largest contact distance.
  std::array<std::int64_t, D> reach{};
  for (int a = 0; a < D; ++a) reach[a] = static_cast<std::int64_t>(std::ceil(2.0 * max_radius / width[a]));

  const auto overlaps = [&](const Vec<D>& x, double r) {
    const auto c = coordinates(x);
    std::array<std::int64_t, D> o{};
    for (int a = 0; a < D; ++a) o[a] = -reach[a];
    while (true) {
      std::array<std::int64_t, D> n{};
      bool inside = true;
      for (int a = 0; a < D; ++a) {
        n[a] = c[a] + o[a];
        if (n[a] < 0 || n[a] >= cells[a]) {
          if (!wraps[a]) inside = false;
          n[a] = ((n[a] % cells[a]) + cells[a]) % cells[a];
        }
      }
      if (inside)
        for (std::int64_t k = head[linear(n)]; k >= 0; k = next[static_cast<std::size_t>(k)]) {
          Vec<D> dx = positions[static_cast<std::size_t>(k)] - x;
          for (int a = 0; a < D; ++a)
            if (wraps[a]) dx[a] -= box.length[a] * std::round(dx[a] / box.length[a]);
          const double contact = r + radii[static_cast<std::size_t>(k)];
          if (dx.squaredNorm() < contact * contact) return true;
        }
      int a = 0;
      for (; a < D; ++a) {
        if (++o[a] <= reach[a]) break;
        o[a] = -reach[a];
      }
      if (a == D) return false;
    }
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
      const auto k = linear(coordinates(x));
      next[i] = head[k];
      head[k] = static_cast<std::int64_t>(i);
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
