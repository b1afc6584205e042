// The gas's keys and its preparation, compiled once for both dimensions:
// every event-driven scenario builds its gas through here.

#include "systems/edmd/gas_setup.hpp"

#include "systems/edmd/compressed_placement.hpp"
#include "systems/edmd/elastic_preparation.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/initial/lattice_placement.hpp"
#include "systems/initial/random_placement.hpp"

namespace granflow::edmd {

void declare_stop_keys(ConfigSchema& schema, double t_stop, double min_energy_fraction) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  schema.real("run.t_stop", t_stop, 0.0, inf, "stop time", true)
      .real_or_infinite("run.max_collisions_per_particle", inf, 0.0, "stop after this many collisions per particle")
      .real("run.min_energy_fraction", min_energy_fraction, 0.0, 1.0,
            "stop when the kinetic energy falls below this fraction of the initial one")
      .allow_change_on_resume("run.t_stop")
      .allow_change_on_resume("run.max_collisions_per_particle")
      .allow_change_on_resume("run.min_energy_fraction");
}

void declare_gas_keys(ConfigSchema& schema, const GasDefaults& d) {
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

// Runs the gas elastically until no trace of the lattice it started on is
// left: the lattice's Bragg peak, of height N at the start, down to what a
// fluid shows (of order 1; above 20 by chance about once in 10^3). A state
// that stays ordered is a solid, not a fluid to start a run from.
namespace {

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

}  // namespace

template <int D>
void build_gas(World& world, const Config& config, std::uint64_t seed,
               const std::function<void(World&)>& customize, const Preparation& preparation) {
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

template void build_gas<2>(World&, const Config&, std::uint64_t, const std::function<void(World&)>&,
                           const Preparation&);
template void build_gas<3>(World&, const Config&, std::uint64_t, const std::function<void(World&)>&,
                           const Preparation&);

}  // namespace granflow::edmd
