#pragma once
// Sites of a simple cubic lattice, in the order a bed is filled: along x
// first, then y, then z (layer by layer from the bottom), each site at
// origin + spacing * (a, b, k) so that a lattice with the origin at 0 puts
// its sites at exact multiples of the spacing.

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "components/vector.hpp"
#include "engine/core/config.hpp"

namespace granflow {

// counts[0] x counts[1] sites per layer, as many layers as `count` sites need.
inline std::vector<Vec<3>> cubic_sites(const Vec<3>& origin, double spacing, const std::array<std::int64_t, 2>& across,
                                       std::size_t count) {
  std::vector<Vec<3>> sites;
  sites.reserve(count);
  const auto row = static_cast<std::size_t>(across[0]), cols = static_cast<std::size_t>(across[1]);
  for (std::size_t k = 0; k < count; ++k)
    sites.emplace_back(origin[0] + spacing * static_cast<double>(k % row),
                       origin[1] + spacing * static_cast<double>((k / row) % cols),
                       origin[2] + spacing * static_cast<double>(k / (row * cols)));
  return sites;
}

// The sites spacing * (a, b, k), a, b, k >= 0, inside [lower, upper) along
// every axis. `what` names the keys in the error when more than 1e8 sites
// would have to be visited.
inline std::vector<Vec<3>> cubic_sites_in(const std::array<double, 3>& lower, const std::array<double, 3>& upper,
                                          double spacing, const std::string& what) {
  double visits = 1.0;
  for (std::size_t a = 0; a < 3; ++a) visits *= std::max(0.0, std::floor(upper[a] / spacing)) + 1.0;
  if (!(visits <= 1e8))
    throw ConfigError(fmt::format("{} gives {:.3g} lattice sites to visit; at most 1e8", what, visits));
  std::vector<Vec<3>> sites;
  for (int k = 0; k * spacing < upper[2]; ++k)
    for (int b = 0; b * spacing < upper[1]; ++b)
      for (int a = 0; a * spacing < upper[0]; ++a) {
        const Vec<3> p(a * spacing, b * spacing, k * spacing);
        if (p[0] >= lower[0] && p[1] >= lower[1] && p[2] >= lower[2]) sites.push_back(p);
      }
  return sites;
}

}  // namespace granflow
