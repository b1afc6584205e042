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
#include "systems/edmd/compressed_placement.hpp"
#include "systems/edmd/elastic_preparation.hpp"
#include "systems/edmd/event_driven_gas.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/initial/lattice_placement.hpp"
#include "systems/initial/random_placement.hpp"
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
inline void declare_stop_keys(ConfigSchema& schema, double t_stop, double min_energy_fraction = 0.0) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  schema.real("run.t_stop", t_stop, 0.0, inf, "stop time", true)
      .real_or_infinite("run.max_collisions_per_particle", inf, 0.0, "stop after this many collisions per particle")
      .real("run.min_energy_fraction", min_energy_fraction, 0.0, 1.0,
            "stop when the kinetic energy falls below this fraction of the initial one")
      .allow_change_on_resume("run.t_stop")
      .allow_change_on_resume("run.max_collisions_per_particle")
      .allow_change_on_resume("run.min_energy_fraction");
}

inline void declare_gas_keys(ConfigSchema& schema, const GasDefaults& d) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  schema.integer("system.dimension", d.dimension, 2, 3, "2 for hard disks, 3 for hard spheres")
      .integer("system.count", d.count, 1, std::numeric_limits<std::int32_t>::max(), "number of particles N")
      .real("system.radius", d.radius, 0.0, inf, "particle radius r", true)
      .real("system.mass", 1.0, 0.0, inf, "particle mass m", true)
      .real("system.box_length", 1.0, 0.0, inf, "edge L of the square/cubic box", true)
      .choice("system.boundary", d.boundary, {"periodic", "reflecting"}, "boundary on every axis")
      .choice("initial.velocity", d.velocity, {"equilibrated", "fixed_speed", "maxwell_boltzmann"},
              "fixed_speed: |v| = initial.speed in random directions; maxwell_boltzmann: at "
              "initial.temperature; equilibrated: fixed_speed run elastically for "
              "initial.equilibration_collisions collisions per particle")
      .choice("initial.placement", "random", {"random", "lattice", "compressed"},
              "random: random sequential addition (packing fractions below its jamming point, 0.384 in 3D and "
              "0.547 in 2D); lattice: a face-centred cubic (3D) or centred square (2D) lattice with random "
              "vacancies, run elastically until it has melted (its Bragg peak gone; a state that stays solid is "
              "refused), then for initial.equilibration_collisions collisions per particle: dense fluids, up "
              "to the freezing point (0.494 in 3D); compressed: random sequential addition at a lower packing "
              "fraction, radii grown in 1 % steps with overlaps pushed apart after each, then run elastically "
              "for 100 and then initial.equilibration_collisions collisions per particle: dense disordered fluids "
              "up to 0.55 (3D) or 0.72 (2D), also past freezing")
      .real("initial.speed", std::numbers::sqrt2, 0.0, inf, "initial speed v0 (fixed_speed, equilibrated)", true)
      .real("initial.temperature", 2.0 / 3.0, 0.0, inf, "initial temperature (maxwell_boltzmann)", true)
      .real("initial.equilibration_collisions", 20.0, 0.0, 1e6,
            "collisions per particle of the elastic run that prepares an equilibrated state or melts the lattice")
      .boolean("initial.remove_mean_velocity", d.remove_mean_velocity,
               "remove the centre-of-mass velocity at start, keeping the kinetic energy");
  CollisionParameters collision;
  collision.restitution = d.restitution;
  CollisionParameters::declare(schema, collision);
  declare_stop_keys(schema, d.t_stop);
}

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

// Runs the gas elastically until no trace of the lattice it started on is
// left: the lattice's Bragg peak, of height N at the start, down to what a
// fluid shows (of order 1; above 20 by chance about once in 10^3). A state
// that stays ordered is a solid, not a fluid to start a run from.
template <int D>
void melt_lattice(World& world, EventDrivenGas<D>& gas, const Vec<D>& bragg_vector, const Preparation& preparation) {
  constexpr double fluid_peak = 20.0;
  constexpr int max_collisions_per_particle = 1000;
  constexpr int slice = 10;
  const auto count = static_cast<double>(world.size());
  for (int done = 0; done < max_collisions_per_particle; done += slice) {
    const auto total = static_cast<std::uint64_t>(std::ceil(slice * count / 2));
    if (run_elastic_preparation(gas, total, preparation.named("melting the lattice")) == StopReason::no_events) return;
    gas.synchronize(gas.time());
    if (structure_factor<D>(world.template component<Position<D>>().values, bragg_vector) < fluid_peak) {
      spdlog::info("lattice melted after {} collisions per particle", done + slice);
      return;
    }
  }
  const auto& radius = world.template component<Radius>().values;
  double occupied = 0.0;
  for (double r : radius) occupied += ball_volume<D>(r);
  throw PlacementError(fmt::format("the lattice has not melted after {} collisions per particle at packing fraction "
                                   "{:.4f}: hard {} freeze above {} and stay solid; lower system.count or "
                                   "system.radius",
                                   max_collisions_per_particle, occupied / world.template resource<Box<D>>().volume(),
                                   D == 3 ? "spheres" : "disks", D == 3 ? "0.494" : "0.70"));
}

// Fills an empty world (of system.count entities) with the configured gas at
// t = 0, or with the stored state initial.from names, as it was stored.
// `customize` may change masses, radii or add components (a mixture's
// species) before particles are placed and given velocities; a stored state
// then replaces the masses, radii and species it set.
// `preparation` hears how far placement and equilibration are and stops
// them when the run is interrupted.
template <int D>
void build_gas(World& world, const Config& config, std::uint64_t seed,
               const std::function<void(World&)>& customize = {}, const Preparation& preparation = {}) {
  const auto count = static_cast<std::size_t>(config.integer("system.count"));
  const bool on_lattice = config.text("initial.placement") == "lattice";
  const bool compressed = config.text("initial.placement") == "compressed";
  const bool stored = starts_from_stored_state(config);
  // Impossible sizes fail here, before anything is allocated.
  if (!customize && !on_lattice && !compressed && !stored) {
    const Box<D> box = box_from<D>(config);
    const double fraction =
        static_cast<double>(count) * ball_volume<D>(config.real("system.radius")) / box.volume();
    if (fraction >= random_sequential_jamming_fraction<D>())
      throw PlacementError(fmt::format("cannot place {} particles at packing fraction {:.4f}: random sequential "
                                       "placement jams at {:.3f} in {}D; lower system.count or system.radius, or "
                                       "set initial.placement = \"lattice\" or \"compressed\"",
                                       count, fraction, random_sequential_jamming_fraction<D>(), D));
  }
  require_memory(fmt::format("system.count = {}", count), bytes_per_particle_estimate * static_cast<double>(count));
  world.resize(count);
  const Box<D>& box = world.emplace_resource<Box<D>>(box_from<D>(config));
  auto& mass = world.add_component<Mass>();
  auto& radius = world.add_component<Radius>();
  auto& position = world.add_component<Position<D>>();
  auto& velocity = world.add_component<Velocity<D>>();
  std::fill(mass.values.begin(), mass.values.end(), config.real("system.mass"));
  std::fill(radius.values.begin(), radius.values.end(), config.real("system.radius"));
  // Periodic images are counted, so that frames can be unwrapped (H5MD `image`).
  if (std::find(box.periodic.begin(), box.periodic.end(), true) != box.periodic.end())
    world.add_component<ImageCount<D>>();
  if (customize) customize(world);
  if (stored) {
    const StoredState state = stored_state_of(config);
    place_stored_state<D>(world, box.length, box.periodic, state);
    spdlog::info("started from {}: {} particles", state.source, state.count);
    return;
  }

  Vec<D> bragg_vector = Vec<D>::Zero();
  if (on_lattice) {
    const double largest = count ? *std::max_element(radius.values.begin(), radius.values.end()) : 0.0;
    auto lattice = place_on_lattice<D>(box, count, largest, seed);
    position.values = std::move(lattice.positions);
    bragg_vector = lattice.bragg_vector;
  } else if (compressed) {
    position.values = place_compressed<D>(box, radius.values, seed, preparation);
  } else {
    PlacementRegion<D> everywhere;
    everywhere.upper = box.length;
    position.values = place_randomly<D>(box, everywhere, radius.values, seed, preparation.named("random placement"));
  }

  const std::string kind = config.text("initial.velocity");
  if (kind == "maxwell_boltzmann")
    velocity.values = maxwell_boltzmann_velocities<D>(mass.values, config.real("initial.temperature"), seed);
  else
    velocity.values = fixed_speed_velocities<D>(count, config.real("initial.speed"), seed);
  if (config.boolean("initial.remove_mean_velocity") && count > 1)
    remove_mean_velocity<D>(velocity.values, mass.values);

  if (kind == "equilibrated" || on_lattice || compressed) {
    const double collisions = config.real("initial.equilibration_collisions");
    const double speed = kind == "maxwell_boltzmann"
                             ? std::sqrt(D * config.real("initial.temperature") / config.real("system.mass"))
                             : config.real("initial.speed");
    check_equilibration_length<D>(box, count, config.real("system.radius"), config.real("system.mass"), speed,
                                  collisions);
    CollisionParameters elastic;
    elastic.wall_restitution = 1.0;
    EventDrivenGas<D> gas(world, elastic);
    gas.start(0.0);
    if (on_lattice) melt_lattice<D>(world, gas, bragg_vector, preparation);
    // Compression leaves many pairs just touching; at packing fraction 0.5
    // the collision rate settles to the fluid's within 2 % after about 80
    // collisions per particle (tests/systems/edmd/compressed_placement_test.cpp).
    if (compressed) {
      constexpr double relaxation_per_particle = 100.0;
      const double relaxation = std::ceil(relaxation_per_particle * static_cast<double>(count) / 2);
      run_elastic_preparation(gas, static_cast<std::uint64_t>(relaxation),
                              preparation.named("relaxing the compressed packing"));
    }
    const auto total = static_cast<std::uint64_t>(std::ceil(collisions * static_cast<double>(count) / 2));
    const StopReason reason = run_elastic_preparation(gas, total, preparation.named("elastic equilibration"));
    gas.synchronize(gas.time());
    // The run proper starts its clock at zero: forget the preparation's
    // collision times, and count images from the state it starts in.
    if (world.has_component<ImageCount<D>>()) {
      auto& image = world.component<ImageCount<D>>();
      std::fill(image.values.begin(), image.values.end(), Eigen::Matrix<std::int32_t, D, 1>::Zero());
    }
    if (world.has_component<LastCollisionTime>()) {
      auto& last = world.component<LastCollisionTime>();
      std::fill(last.values.begin(), last.values.end(), -std::numeric_limits<double>::infinity());
    }
    spdlog::info("{}: {:.1f} collisions per particle in t = {:.4g}{}",
                 on_lattice   ? "lattice melted and equilibrated elastically"
                 : compressed ? "compressed and equilibrated elastically"
                              : "equilibrated elastically",
                 2.0 * static_cast<double>(gas.statistics().pair_collisions) / static_cast<double>(count),
                 gas.time(), reason == StopReason::no_events ? " (no more events: the gas is at rest)" : "");
  }
}

}  // namespace granflow::edmd
