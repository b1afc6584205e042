#pragma once
// Small hard-sphere worlds for tests: random non-overlapping positions and
// Maxwell-Boltzmann velocities (T = 1, zero total momentum).

#include <cmath>
#include <cstdint>

#include "components/box.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/world.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/initial/random_placement.hpp"

namespace granflow::edmd::testing {

template <int D>
double radius_for_packing_fraction(std::size_t count, double eta, double box_length = 1.0) {
  return theory::radius_for_packing_fraction<D>(static_cast<double>(count), eta, std::pow(box_length, D));
}

template <int D>
void fill_gas(World& world, std::size_t count, double radius, bool periodic, std::uint64_t seed,
              double temperature = 1.0, double box_length = 1.0) {
  world.resize(count);
  Box<D> box;
  box.length.fill(box_length);
  box.periodic.fill(periodic);
  world.emplace_resource<Box<D>>(box);
  auto& mass = world.add_component<Mass>();
  auto& r = world.add_component<Radius>();
  std::fill(mass.values.begin(), mass.values.end(), 1.0);
  std::fill(r.values.begin(), r.values.end(), radius);
  PlacementRegion<D> region;
  region.upper = box.length;
  world.add_component<Position<D>>().values = place_randomly<D>(box, region, r.values, seed);
  auto velocity = maxwell_boltzmann_velocities<D>(mass.values, temperature, seed);
  remove_mean_velocity<D>(velocity, mass.values);
  world.add_component<Velocity<D>>().values = velocity;
}

}  // namespace granflow::edmd::testing
