// Crater formation by a projectile hitting a granular bed . N equal disks fill y < bed.height of a unit box with reflecting walls
// at packing fraction bed.packing_fraction, at rest; a projectile of
// mass_ratio m0 and radius_ratio r0 starts at (x, y) moving straight down.
//
// The bed is built as a melted lattice (systems/edmd/melted_lattice.hpp):
// random sequential addition jams at 0.547 in 2D and takes very long near
// 0.5, so disks start on a triangular lattice with random vacancies and an
// elastic run of bed.melt_collisions collisions per particle inside the bed
// region turns it into an equilibrium hard-disk fluid; then all are stopped.
//
// Stop: when run.min_energy_fraction (0.1) of the initial energy is left, as
// in the original problem. Scans in xi should stop at a fixed time instead
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

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <numbers>

#include "components/species.hpp"
#include "engine/core/output_times.hpp"
#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/edmd/crater_bed.hpp"
#include "systems/edmd/event_driven_run.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/observables/collisions_per_particle.hpp"
#include "systems/observables/crater.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/particle_frames.hpp"

namespace granflow::scenarios {

namespace {

void declare_keys(ConfigSchema& s) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  s.integer("system.count", 5000, 2, 10000000, "number N of bed disks (the projectile comes on top)")
      .real("system.mass", 1.0, 0.0, inf, "mass m0 of a bed disk", true)
      .real("bed.packing_fraction", 0.5, 0.0, 0.85, "packing fraction of the bed region", true)
      .real("bed.height", 0.5, 0.0, 1.0, "the bed fills 0 <= y <= bed.height", true)
      .real("bed.melt_collisions", 20.0, 0.0, 1e4,
            "elastic collisions per particle that melt the initial lattice of the bed")
      .real("projectile.mass_ratio", 25.0, 0.0, inf, "projectile mass over m0", true)
      .real("projectile.radius_ratio", 5.0, 0.0, inf, "projectile radius over the bed radius r0", true)
      .real("projectile.speed", 5.0, 0.0, inf, "projectile speed v0 (moving in -y)", true)
      .real("projectile.x", 0.5, 0.0, 1.0, "projectile start x")
      .real("projectile.y", 0.75, 0.0, 1.0, "projectile start y");
  edmd::CollisionParameters collision;
  collision.restitution = 0.5;
  collision.wall_restitution = 0.5;
  collision.contact_time = 1e-7;
  collision.collapse_rate_factor = 1e5;
  edmd::CollisionParameters::declare(s, collision);
  edmd::declare_stop_keys(s, 10.0, 0.1);
  s.real("crater.displacement_threshold", 1.0, 0.0, inf,
         "a bed disk moved farther than this many bed radii belongs to the crater", true)
      .real("output.interval", 0.005, 0.0, inf, "time between outputs of the observables", true);
  declare_frame_keys(s, "first_last", {"none", "first_last", "all"});
}

void build(Run& run) {
  const Config& c = run.config();
  const double r0 = edmd::bed_radius(c);
  run.initial_state([&](World& world) {
    edmd::build_crater(world, c, run.preparation("setup"));
    run.derive("bed_radius", r0);
    run.derive("projectile_radius", c.real("projectile.radius_ratio") * r0);
    run.derive("initial_kinetic_energy", total_kinetic_energy<2>(world));
  });
  Box<2> box;
  box.length.fill(1.0);
  box.periodic.fill(false);
  const double energy0 = run.derived("initial_kinetic_energy");
  auto& gas = edmd::add_event_driven_gas<2>(run, box, edmd::CollisionParameters::from(c),
                                            edmd::advance_limits_from(c, run.world().size(), energy0), energy0);
  if (!run.resuming()) gas.synchronize(0.0);
  check_output_count(c.real("run.t_stop"), c.real("output.interval"));
  const auto outputs = std::make_shared<EveryTime>(c.real("output.interval"), c.real("run.t_stop"));
  run.observe<KineticEnergyObserver<2>>(outputs);
  run.observe<CollisionsPerParticleObserver<2>>(outputs);
  auto& crater = run.observe<CraterObserver<2>>(outputs, run.world(), c.real("crater.displacement_threshold") * r0,
                                                c.real("bed.height"));
  run.keep("crater", crater);
  add_particle_frames<2>(run, outputs);
  run.stop_at_time(c.real("run.t_stop"));
  run.at_finish([&run, &gas, energy0](H5mdFile& file, const RunOutcome&) {
    const double energy = total_kinetic_energy<2>(run.world());
    const auto& stats = gas.statistics();
    file.write_attribute("/observables", "initial_kinetic_energy", energy0);
    file.write_attribute("/observables", "final_kinetic_energy", energy);
    spdlog::info("t = {:.4g}: crater of {} disks, {:.3g} of the energy left, {} collisions; energy balance {:.2e} "
                 "of E0",
                 gas.time(), run.world().resource<ObservableStore>().slot("crater_size").value.at(0),
                 energy / energy0, stats.pair_collisions,
                 (energy0 - energy - stats.dissipated_energy - stats.wall_dissipated_energy) / energy0);
  });
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(crater_impact, Scenario{
  .name = "crater_impact",
  .summary = "a heavy projectile hits a resting bed of disks; crater size and penetration (EDMD)",
  .default_output = "crater.h5md",
  .keys = declare_keys,
  .build = build,
})

}  // namespace granflow::scenarios
