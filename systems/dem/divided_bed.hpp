#pragma once
// The initial bed of a box split by a divider at x = divider_x: the spheres
// alternately left and right of it, each half on a simple cubic lattice of
// spacing 2.2 r from just above the floor's highest point up, refused with
// the keys named where they do not fit below the top of the box.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "components/vector.hpp"
#include "engine/core/config.hpp"
#include "systems/initial/cubic_lattice.hpp"

namespace granflow::dem {

// `floor_top`: the highest the floor reaches (2A for the wiggle motion, A for sine).
inline std::vector<Vec<3>> divided_bed_sites(const std::array<double, 3>& box, double divider_x, std::size_t count,
                                             double radius, double floor_top) {
  const double spacing = 2.2 * radius;
  const auto per_row = [&](double width) {
    return static_cast<std::int64_t>(std::max(0, static_cast<int>(std::floor((width - 2 * radius) / spacing)) + 1));
  };
  const std::int64_t across_y = per_row(box[1]);
  const std::array<std::int64_t, 2> across_x{per_row(divider_x - 0.2 * radius), per_row(box[0] - divider_x - 0.2 * radius)};
  const double floor_clearance = floor_top + 1.1 * radius;
  const auto layers_needed = [&](std::size_t side) {
    const double per_layer = static_cast<double>(across_x[side] * across_y);
    return per_layer > 0 ? std::ceil((static_cast<double>(count) / 2 + 1) / per_layer) : 1e300;
  };
  if (floor_clearance + spacing * std::max(layers_needed(0), layers_needed(1)) > box[2] - radius)
    throw ConfigError(fmt::format("system.count = {} spheres of radius {} do not fit below the top of the box "
                                  "(system.box z = {})", count, radius, box[2]));
  std::array<std::vector<Vec<3>>, 2> halves;
  for (std::size_t side : {0u, 1u})
    halves[side] = cubic_sites({side == 0 ? radius + 0.1 * radius : divider_x + radius + 0.1 * radius, radius,
                                floor_clearance},
                               spacing, {across_x[side], across_y}, (count + 1 - side) / 2);
  std::vector<Vec<3>> sites(count);
  for (std::size_t i = 0; i < count; ++i) sites[i] = halves[i % 2][i / 2];
  return sites;
}

}  // namespace granflow::dem
