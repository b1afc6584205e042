#pragma once
// Dense random packings of equal disks, beyond what random sequential
// addition reaches quickly (it jams at a packing fraction of 0.547 in 2D and
// slows down long before): disks start on a triangular lattice with randomly
// chosen vacant sites, filling the region evenly, and an elastic
// event-driven run of a few tens of collisions per particle inside the
// region's own reflecting walls melts the lattice into an equilibrium hard-disk
// fluid. Hard disks stay fluid up to a packing fraction of about 0.70, so
// this reaches the crater bed (0.5) or denser in seconds.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <vector>

#include <fmt/format.h>

#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/world.hpp"
#include "systems/edmd/elastic_preparation.hpp"
#include "systems/edmd/event_driven_gas.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/initial/lattice_placement.hpp"
#include "systems/initial/random_placement.hpp"

namespace granflow {

// Centres of `count` disks of `radius` in [0, width] x [0, height], not
// overlapping each other or the region's edges, melted for
// `melt_collisions` collisions per particle. Positions are relative to the
// region's lower left corner.
inline std::vector<Vec<2>> place_melted_lattice(std::size_t count, double radius, double width, double height,
                                                double melt_collisions, std::uint64_t seed,
                                                const Preparation& preparation = {}) {
  const double inner_w = width - 2.0 * radius, inner_h = height - 2.0 * radius;
  const double fraction = static_cast<double>(count) * std::numbers::pi * radius * radius / (width * height);
  if (inner_w <= 0 || inner_h <= 0)
    throw PlacementError(fmt::format("region {} x {} is narrower than a disk of radius {}", width, height, radius));
  // Triangular lattice of spacing a: rows a*sqrt(3)/2 apart, odd rows shifted by a/2.
  const auto sites_for = [&](double a) {
    const auto columns = static_cast<std::size_t>(std::floor(inner_w / a)) + 1;
    const auto rows = static_cast<std::size_t>(std::floor(inner_h / (a * std::sqrt(3.0) / 2.0))) + 1;
    std::vector<Vec<2>> sites;
    for (std::size_t row = 0; row < rows; ++row) {
      const double shift = row % 2 ? 0.5 * a : 0.0;
      for (std::size_t column = 0; column < columns; ++column) {
        const double x = radius + shift + static_cast<double>(column) * a;
        if (x <= width - radius) sites.emplace_back(x, radius + static_cast<double>(row) * a * std::sqrt(3.0) / 2.0);
      }
    }
    return sites;
  };
  // Widest spacing that still offers `count` sites, bracketed around the
  // spacing whose cells would tile the region (area a^2 sqrt(3)/2 per site),
  // so a dilute bed never builds the (1/radius)^2 sites of the densest lattice.
  const double tiling = std::sqrt(inner_w * inner_h * 2.0 / (std::sqrt(3.0) * static_cast<double>(count)));
  double lo = std::max(2.0 * radius, 0.25 * tiling), hi = std::max(inner_w, inner_h) + 2.0 * radius;
  if (lo > 2.0 * radius && sites_for(lo).size() < count) lo = 2.0 * radius;
  if (sites_for(lo).size() < count)
    throw PlacementError(fmt::format("cannot place {} disks of radius {} in {} x {}: packing fraction {:.4f} exceeds "
                                     "what a triangular lattice in this region holds",
                                     count, radius, width, height, fraction));
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (sites_for(mid).size() >= count ? lo : hi) = mid;
  }
  std::vector<Vec<2>> sites = sites_for(lo);
  keep_random_sites<2>(sites, count, seed);
  if (melt_collisions <= 0.0 || count < 2) return sites;

  World world(count);
  Box<2> box;
  box.length = {width, height};
  box.periodic.fill(false);
  world.emplace_resource<Box<2>>(box);
  world.add_component<Mass>().values.assign(count, 1.0);
  world.add_component<Radius>().values.assign(count, radius);
  world.add_component<Position<2>>().values = sites;
  auto& velocity = world.add_component<Velocity<2>>();
  for (std::size_t i = 0; i < count; ++i) {
    Philox random(stream::melt_velocity, seed, 0, i);
    velocity[i] = random_direction<2>(random);
  }
  edmd::EventDrivenGas<2> gas(world, edmd::CollisionParameters{}, false);
  gas.start(0.0);
  edmd::run_elastic_preparation(gas, static_cast<std::uint64_t>(std::ceil(melt_collisions * static_cast<double>(count) / 2)),
                                preparation.named("melting the bed"));
  gas.synchronize(gas.time());
  return world.component<Position<2>>().values;
}

}  // namespace granflow
