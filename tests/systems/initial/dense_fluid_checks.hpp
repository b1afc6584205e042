#pragma once
// What the tests of dense initial states check: that no two particles
// overlap, and that the elastic gas built from a placement collides at the
// equilibrium fluid's rate (Enskog's, with the Carnahan-Starling contact
// value), which a crystal or a packing still jammed would miss.

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "systems/edmd/event_driven_gas.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "tests/scenario_schema.hpp"

namespace granflow::testing {

// Smallest centre distance over contact distance of any pair, by brute force.
template <int D>
double closest_relative(const std::vector<Vec<D>>& x, const std::vector<double>& radius, const Box<D>& box) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      Vec<D> d = x[j] - x[i];
      for (int a = 0; a < D; ++a)
        if (box.periodic[a]) d[a] -= box.length[a] * std::round(d[a] / box.length[a]);
      best = std::min(best, d.norm() / (radius[i] + radius[j]));
    }
  return best;
}

// Hard spheres at packing fraction `eta` in the unit periodic box, placed by
// `placement` with Maxwell-Boltzmann velocities and 20 elastic collisions per
// particle of preparation.
inline Config dense_gas_config(std::size_t count, double eta, const std::string& placement) {
  Config config(scenario_schema("haff_cooling"));
  config.set("system.count", static_cast<std::int64_t>(count));
  config.set("system.radius", theory::radius_for_packing_fraction<3>(static_cast<double>(count), eta, 1.0));
  config.set("initial.placement", placement);
  config.set("initial.velocity", std::string("maxwell_boltzmann"));
  config.set("initial.equilibration_collisions", 20.0);
  return config;
}

// The collision rate of the gas built in `world` (equal spheres at packing
// fraction `eta`) over the next 20 collisions per particle, over Enskog's.
inline double collision_rate_over_enskog(World& world, double eta) {
  const std::size_t count = world.size();
  const double radius = world.component<Radius>()[0];
  edmd::EventDrivenGas<3> gas(world, edmd::CollisionParameters{});
  gas.start(0.0);
  edmd::AdvanceLimits limits;
  limits.max_pair_collisions = 20 * count / 2;
  gas.advance(std::numeric_limits<double>::infinity(), limits);
  const double temperature = 2.0 * gas.kinetic_energy() / (3.0 * static_cast<double>(count));
  const double measured =
      2.0 * static_cast<double>(gas.statistics().pair_collisions) / (static_cast<double>(count) * gas.time());
  return measured / theory::collision_frequency<3>(static_cast<double>(count), 2 * radius, temperature, 1.0, eta);
}

}  // namespace granflow::testing
