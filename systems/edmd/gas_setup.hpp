#pragma once
// Builds a hard-sphere (hard-disk) gas from a configuration: the box, the
// components, non-overlapping positions (random, or a melted lattice for
// dense fluids) and the initial velocities, including an elastically
// equilibrated state. Scenarios share the keys
// declared here so every EDMD scenario is configured the same way.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <string>

#include <spdlog/spdlog.h>

#include "components/box.hpp"
#include "components/image_count.hpp"
#include "components/last_collision_time.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/config.hpp"
#include "engine/core/memory_check.hpp"
#include "engine/core/world.hpp"
#include "engine/run/preparation.hpp"
#include "systems/edmd/event_driven_gas.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "systems/initial/stored_start.hpp"

namespace granflow::edmd {

struct GasDefaults {
  std::int64_t dimension = 3;
  std::int64_t count = 1000;
  double radius = 0.025;
  std::string boundary = "periodic";
  std::string velocity = "equilibrated";
  double restitution = 0.8;
  double t_stop = 100.0;
  bool remove_mean_velocity = true;
};

// run.* stop criteria of event-driven runs; a resumed run may change them.
void declare_stop_keys(ConfigSchema& schema, double t_stop, double min_energy_fraction = 0.0);

// system.*, initial.*, collision.* and run.* keys of a hard-sphere gas.
void declare_gas_keys(ConfigSchema& schema, const GasDefaults& d);

template <int D>
Box<D> box_from(const Config& config) {
  Box<D> box;
  box.length.fill(config.real("system.box_length"));
  box.periodic.fill(config.text("system.boundary") == "periodic");
  return box;
}

// Stop criteria of a run from run.max_collisions_per_particle and
// run.min_energy_fraction (of the initial kinetic energy energy0).
inline AdvanceLimits advance_limits_from(const Config& config, std::size_t count, double energy0) {
  AdvanceLimits limits;
  const double max_cpp = config.real("run.max_collisions_per_particle");
  if (std::isfinite(max_cpp))
    limits.max_pair_collisions = static_cast<std::uint64_t>(std::ceil(max_cpp * static_cast<double>(count) / 2));
  limits.min_kinetic_energy = config.real("run.min_energy_fraction") * energy0;
  return limits;
}

// What an event-driven gas holds per particle (the engine's figure is
// 190-200 bytes, docs/performance.md) plus the placement's scratch space.
inline constexpr double bytes_per_particle_estimate = 280.0;

// Events an elastic run of `collisions` per particle needs: the collisions
// and the cell crossings in between (Enskog collision frequency; cells at
// least a diameter wide, at most 3 per particle). A dilute gas of tiny
// particles crosses cells ~1/r^2 times per collision; this is refused when it
// could not finish and warned about when it takes hours.
// `keys` names the settings in the refusal.
template <int D>
void check_equilibration_length(const Box<D>& box, std::size_t count, double radius, double mass, double speed,
                                double collisions,
                                const std::string& keys = "initial.equilibration_collisions, system.radius, "
                                                          "system.count; or use initial.velocity = "
                                                          "\"maxwell_boltzmann\"") {
  if (count < 2 || collisions <= 0) return;
  const auto n = static_cast<double>(count);
  const double volume = box.volume();
  const double temperature = mass * speed * speed / D;
  const double omega = theory::collision_frequency<D>(n / volume, 2 * radius, temperature, mass,
                                                      theory::packing_fraction<D>(n, radius, volume));
  const double duration = collisions / omega;
  const double width = std::max(2 * radius, std::pow(volume / (3.0 * n), 1.0 / D));
  const double axis_speed = std::sqrt(2.0 * temperature / (std::numbers::pi * mass));
  const double events = collisions * n / 2 + n * duration * D * axis_speed / width;
  constexpr double events_per_hour = 3.6e9;  // about 1 us per event
  if (events > 1e4 * events_per_hour)
    throw ConfigError(fmt::format("the elastic equilibration ({} collisions per particle) would need about {:.2g} "
                                  "events (~{:.2g} hours): the gas is too dilute for particles of radius {}; "
                                  "change {}",
                                  collisions, events, events / events_per_hour, radius, keys));
  if (events > events_per_hour)
    spdlog::warn("the elastic equilibration will need about {:.2g} events (~{:.2g} hours)", events,
                 events / events_per_hour);
}

// Fills an empty world (of system.count entities) with the configured gas at
// t = 0, or with the stored state initial.from names, as it was stored.
// `customize` may change masses, radii or add components (a mixture's
// species) before particles are placed and given velocities; a stored state
// then replaces the masses, radii and species it set.
// `preparation` hears how far placement and equilibration are and stops
// them when the run is interrupted.
// Compiled once for 2 and 3 dimensions (gas_setup.cpp).
template <int D>
void build_gas(World& world, const Config& config, std::uint64_t seed,
               const std::function<void(World&)>& customize = {}, const Preparation& preparation = {});
extern template void build_gas<2>(World&, const Config&, std::uint64_t, const std::function<void(World&)>&,
                                  const Preparation&);
extern template void build_gas<3>(World&, const Config&, std::uint64_t, const std::function<void(World&)>&,
                                  const Preparation&);

}  // namespace granflow::edmd
