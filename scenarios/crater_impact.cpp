// Crater formation by a projectile hitting a granular bed (seed 002 problem
// 4). N equal disks fill y < bed.height of a unit box with reflecting walls
// at packing fraction bed.packing_fraction, at rest; a projectile of
// mass_ratio m0 and radius_ratio r0 starts at (x, y) moving straight down.
//
// The bed is built as a melted lattice (systems/initial/melted_lattice.hpp):
// random sequential addition jams at 0.547 in 2D and takes very long near
// 0.5, so disks start on a triangular lattice with random vacancies and an
// elastic run of bed.melt_collisions collisions per particle inside the bed
// region turns it into an equilibrium hard-disk fluid; then all are stopped.
//
// Stop: when run.min_energy_fraction (0.1) of the initial energy is left, as
// in the seed. Scans in xi should stop at a fixed time instead
// (run.min_energy_fraction = 0, run.t_stop), since weakly dissipative beds
// keep their energy for very long (docs/scenarios.md).
//
// TC model: a resting bed hit with xi = 0.5 collapses without it (clusters of
// touching disks exchange ever faster collisions). collision.contact_time =
// 1e-7 is 1e-4 of the time r0 / v0 a projectile needs to move a bed radius
// (r0 = 0.0056 for N = 5000, v0 = 5: 1.1e-3), so it only acts inside such
// clusters and leaves the impact dynamics alone. The collapse alarm on the
// collision rate (collision.collapse_rate_factor) is set to 1e5 instead of
// the gas scenarios' 1e3: a heavy projectile compacts the bed ahead of it,
// where disks collide ~1e3 times faster than the bed's mean thermal speed
// suggests without collapsing; an actual collapse still stops the run when
// time stops advancing.

#include "scenarios/crater_impact.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <numbers>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/species.hpp"
#include "components/velocity.hpp"
#include "engine/h5md_file.hpp"
#include "engine/observable_store.hpp"
#include "engine/profiler.hpp"
#include "engine/progress.hpp"
#include "engine/run_control.hpp"
#include "engine/schedule.hpp"
#include "systems/edmd/event_driven_step.hpp"
#include "systems/edmd/event_statistics_output.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/initial/melted_lattice.hpp"
#include "systems/observables/collisions_per_particle.hpp"
#include "systems/observables/crater.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/observable_writer.hpp"
#include "systems/observables/particle_snapshot.hpp"

namespace granflow::scenarios {

const ConfigSchema& crater_impact_schema() {
  static const ConfigSchema schema = [] {
    constexpr double inf = std::numeric_limits<double>::infinity();
    ConfigSchema s;
    s.choice("scenario", "crater_impact", {"crater_impact"}, "scenario name")
        .integer("system.count", 5000, 2, 10000000, "number N of bed disks (the projectile comes on top)")
        .real("system.mass", 1.0, 0.0, inf, "mass m0 of a bed disk", true)
        .real("bed.packing_fraction", 0.5, 0.0, 0.85, "packing fraction of the bed region", true)
        .real("bed.height", 0.5, 0.0, 1.0, "the bed fills 0 <= y <= bed.height", true)
        .real("bed.melt_collisions", 20.0, 0.0, 1e4,
              "elastic collisions per particle that melt the initial lattice of the bed")
        .real("projectile.mass_ratio", 25.0, 0.0, inf, "projectile mass over m0", true)
        .real("projectile.radius_ratio", 5.0, 0.0, inf, "projectile radius over the bed radius r0", true)
        .real("projectile.speed", 5.0, 0.0, inf, "projectile speed v0 (moving in -y)", true)
        .real("projectile.x", 0.5, 0.0, 1.0, "projectile start x")
        .real("projectile.y", 0.75, 0.0, 1.0, "projectile start y")
        .real("collision.restitution", 0.5, 0.0, 1.0, "normal restitution coefficient xi")
        .real("collision.wall_restitution", 0.5, 0.0, 1.0, "restitution of the box walls (seed 002 eqs. 3-4)")
        .real("collision.contact_time", 1e-7, 0.0, inf,
              "TC model: collisions within this time of a particle's previous collision are elastic")
        .real_or_infinite("collision.collapse_rate_factor", 1e5, 10.0,
                          "collision-rate increase (at equal thermal speed) that is reported as inelastic collapse")
        .real("run.t_stop", 10.0, 0.0, inf, "stop time", true)
        .real("run.min_energy_fraction", 0.1, 0.0, 1.0, "stop when the kinetic energy falls below this fraction")
        .real_or_infinite("run.max_collisions_per_particle", inf, 0.0, "stop after this many collisions per particle")
        .integer("run.seed", 1, 0, std::numeric_limits<std::int64_t>::max(), "seed of every random stream")
        .real("crater.displacement_threshold", 1.0, 0.0, inf,
              "a bed disk moved farther than this many bed radii belongs to the crater", true)
        .real("output.interval", 0.005, 0.0, inf, "time between outputs of the observables", true)
        .choice("output.positions", "first_last", {"none", "first_last", "all"},
                "particle frames: none, before the impact and at the end, or at every output");
    return s;
  }();
  return schema;
}

double bed_radius(const Config& config) {
  const double area = config.real("bed.height");  // the box is 1 wide
  return std::sqrt(config.real("bed.packing_fraction") * area /
                   (static_cast<double>(config.integer("system.count")) * std::numbers::pi));
}

void build_crater(World& world, const Config& config) {
  const auto count = static_cast<std::size_t>(config.integer("system.count"));
  const double r0 = bed_radius(config);
  const double big = config.real("projectile.radius_ratio") * r0;
  const double x = config.real("projectile.x"), y = config.real("projectile.y");
  const double height = config.real("bed.height");
  if (x - big < 0 || x + big > 1 || y + big > 1 || y - big < height)
    throw ConfigError(fmt::format("projectile of radius {:.4g} at ({}, {}) must lie inside the box and above the bed "
                                  "(bed.height = {}); change projectile.x/y or projectile.radius_ratio",
                                  big, x, y, height));
  world.resize(count + 1);
  Box<2> box;
  box.length.fill(1.0);
  box.periodic.fill(false);
  world.emplace_resource<Box<2>>(box);
  auto& mass = world.add_component<Mass>();
  auto& radius = world.add_component<Radius>();
  auto& species = world.add_component<Species>();
  auto& position = world.add_component<Position<2>>();
  auto& velocity = world.add_component<Velocity<2>>();
  const auto bed = place_melted_lattice(count, r0, 1.0, height, config.real("bed.melt_collisions"),
                                        static_cast<std::uint64_t>(config.integer("run.seed")));
  for (std::size_t i = 0; i < count; ++i) {
    mass[i] = config.real("system.mass");
    radius[i] = r0;
    position[i] = bed[i];
    velocity[i].setZero();
  }
  mass[count] = config.real("projectile.mass_ratio") * config.real("system.mass");
  radius[count] = big;
  species[count] = 1;
  position[count] = Vec<2>(x, y);
  velocity[count] = Vec<2>(0.0, -config.real("projectile.speed"));
}

int run_crater_impact(const Config& config, const RunOptions& options) {
  const auto count = static_cast<std::size_t>(config.integer("system.count"));
  const std::string output_path = options.output_path.empty() ? "crater.h5" : options.output_path;
  spdlog::info("crater_impact: N = {} bed disks, seed = {}", count, config.integer("run.seed"));
  H5mdFile file(output_path, "crater_impact");
  file.write_parameters(config);

  World world;
  build_crater(world, config);
  const double r0 = bed_radius(config);
  const auto& box = world.resource<Box<2>>();
  file.write_box(box.edges(), box.h5md_boundary());
  file.write_attribute("/parameters/derived", "bed_radius", r0);
  file.write_attribute("/parameters/derived", "projectile_radius", config.real("projectile.radius_ratio") * r0);

  edmd::EventDrivenGas<2> gas(world, edmd::collision_parameters_from(config));
  gas.start(0.0);
  gas.synchronize(0.0);
  std::vector<Vec<2>> initial(world.size());
  {
    const auto& id = world.component<ParticleId>();
    const auto& x = world.component<Position<2>>();
    for (std::size_t i = 0; i < world.size(); ++i) initial[id[i]] = x[i];
  }
  const double energy0 = total_kinetic_energy<2>(world);

  world.emplace_resource<Clock>();
  auto& control = world.emplace_resource<RunControl>();
  auto& store = world.emplace_resource<ObservableStore>();
  const std::vector<std::string> observables{"kinetic_energy", "temperature", "collisions_per_particle",
                                             "crater_size", "projectile_depth"};
  for (const auto& name : observables) store.declare(name);
  const edmd::AdvanceLimits limits = edmd::advance_limits_from(config, world.size(), energy0);

  Profiler profiler;
  Schedule schedule(profiler);
  schedule.emplace<edmd::EventDrivenStep<2>>(gas, limits);
  schedule.emplace<KineticEnergyObserver<2>>();
  schedule.emplace<CollisionsPerParticleObserver<2>>(gas);
  schedule.emplace<CraterObserver<2>>(initial, config.real("crater.displacement_threshold") * r0,
                                      config.real("bed.height"));
  schedule.emplace<ObservableWriter>(file, observables);

  const std::string frames = config.text("output.positions");
  if (frames != "none") append_particle_frame<2>(file, world, 0, 0.0);
  const double t_stop = config.real("run.t_stop");
  const double interval = config.real("output.interval");
  Progress progress("crater_impact", "collisions/s", options.progress);
  control.target_time = 0.0;
  schedule.run(world);
  for (std::uint64_t k = 1; !control.stop; ++k) {
    control.target_time = std::min(t_stop, static_cast<double>(k) * interval);
    schedule.run(world);
    if (frames == "all") append_particle_frame<2>(file, world, world.resource<Clock>().step, gas.time());
    const double remaining = gas.kinetic_energy() / energy0;
    const double fraction_by_energy =
        limits.min_kinetic_energy > 0 ? std::log(remaining) / std::log(config.real("run.min_energy_fraction")) : 0.0;
    progress.update(std::max(gas.time() / t_stop, fraction_by_energy),
                    static_cast<double>(gas.statistics().pair_collisions));
    if (gas.time() >= t_stop) break;
  }
  progress.finish();
  if (frames == "first_last") append_particle_frame<2>(file, world, world.resource<Clock>().step, gas.time());

  const auto& stats = gas.statistics();
  write_particle_constants(file, world);
  const double crater = store.slot("crater_size").value.at(0);
  const double energy = total_kinetic_energy<2>(world);
  file.write_attribute("/observables", "stop_reason", control.stop ? control.reason : "reached run.t_stop");
  file.write_attribute("/observables", "initial_kinetic_energy", energy0);
  file.write_attribute("/observables", "final_kinetic_energy", energy);
  edmd::write_event_statistics(file, stats);
  file.write_profile(profiler.entries());
  file.finish();
  spdlog::info("t = {:.4g}: crater of {} disks, {:.3g} of the energy left, {} collisions; energy balance "
               "{:.2e} of E0; wrote {}",
               gas.time(), crater, energy / energy0, stats.pair_collisions,
               (energy0 - energy - stats.dissipated_energy - stats.wall_dissipated_energy) / energy0, output_path);
  if (options.profile) fmt::print("{}", profiler.table());
  if (control.failed) {
    spdlog::error("{}", control.reason);
    return 3;
  }
  return 0;
}

}  // namespace granflow::scenarios
