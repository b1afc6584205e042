// Two-mass hard-disk gas: elastic collisions bring
// both species to the same mean kinetic energy (equipartition); inelastic
// ones do not, and the heavy species stays hotter. The statistical error is
// measured from snapshots two collisions per particle apart, which are close
// to independent.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "engine/core/sample_statistics.hpp"
#include "scenarios/mixture.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/observables/species_kinetic_energy.hpp"
#include "tests/scenario_schema.hpp"

namespace granflow::scenarios {
namespace {

// Heavy over light mean kinetic energy in `snapshots` snapshots, `between`
// collisions per particle apart, starting now.
MeanAndError energy_ratio(edmd::EventDrivenGas<2>& gas, World& world, int snapshots, double between) {
  std::vector<double> ratios;
  const auto start = gas.statistics().pair_collisions;
  for (int s = 1; s <= snapshots; ++s) {
    edmd::AdvanceLimits limits;
    limits.max_pair_collisions = start + static_cast<std::uint64_t>(s * between * static_cast<double>(world.size()) / 2);
    gas.advance(INFINITY, limits);
    gas.synchronize(gas.time());
    const auto energy = species_kinetic_energies<2>(world, 2);
    ratios.push_back(energy[1] / energy[0]);
  }
  return mean_and_standard_error(ratios);
}

// Runs `collisions_per_particle` more collisions per particle.
void run_for(edmd::EventDrivenGas<2>& gas, const World& world, double collisions_per_particle) {
  edmd::AdvanceLimits limits;
  limits.max_pair_collisions = gas.statistics().pair_collisions +
                               static_cast<std::uint64_t>(collisions_per_particle * static_cast<double>(world.size()) / 2);
  gas.advance(INFINITY, limits);
}

Config mixture_config() {
  Config config(scenario_schema("mixture"));
  config.set("system.count", std::int64_t{4000});
  return config;
}

TEST(Mixture, ElasticSpeciesShareTheKineticEnergy) {
  const Config config = mixture_config();
  World world;
  edmd::build_gas<2>(world, config, 1, mixture_species(config));
  // All start at one speed: the heavy species holds 4 times the energy.
  const auto start = species_kinetic_energies<2>(world, 2);
  ASSERT_NEAR(start[1] / start[0], 4.0, 1e-12);
  edmd::EventDrivenGas<2> gas(world, edmd::CollisionParameters::from(config));
  gas.start(0.0);
  run_for(gas, world, 10.0);
  const MeanAndError ratio = energy_ratio(gas, world, 20, 2.0);
  std::printf("xi = 1: heavy/light mean kinetic energy %.4f +- %.4f\n", ratio.mean, ratio.standard_error);
  // 2000 particles per species: the ratio fluctuates by ~sqrt(2/2000)*sqrt(2) ~ 4 % per snapshot.
  EXPECT_LT(ratio.standard_error, 0.02);
  EXPECT_NEAR(ratio.mean, 1.0, 4.0 * ratio.standard_error) << "standard error " << ratio.standard_error;
}

TEST(Mixture, InelasticHeavySpeciesIsHotter) {
  Config config = mixture_config();
  World world;
  edmd::build_gas<2>(world, config, 1, mixture_species(config));
  // Start from equipartition, so a hotter heavy species is not left over from the start.
  {
    edmd::EventDrivenGas<2> elastic(world, edmd::CollisionParameters::from(config));
    elastic.start(0.0);
    run_for(elastic, world, 10.0);
    elastic.synchronize(elastic.time());
  }
  const auto equal = species_kinetic_energies<2>(world, 2);
  ASSERT_NEAR(equal[1] / equal[0], 1.0, 0.15);
  config.set("collision.restitution", 0.8);
  edmd::EventDrivenGas<2> gas(world, edmd::CollisionParameters::from(config));
  gas.start(0.0);
  run_for(gas, world, 5.0);
  const MeanAndError ratio = energy_ratio(gas, world, 10, 1.0);
  std::printf("xi = 0.8: heavy/light mean kinetic energy %.4f +- %.4f\n", ratio.mean, ratio.standard_error);
  EXPECT_GT(ratio.mean - 1.0, 5.0 * ratio.standard_error) << "ratio " << ratio.mean << " +- " << ratio.standard_error;
  EXPECT_GT(ratio.mean, 1.1);
}

}  // namespace
}  // namespace granflow::scenarios
