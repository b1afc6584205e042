// Homogeneous cooling of a granular gas: N inelastic hard spheres (disks) in a
// periodic box, equilibrated elastically, then cooling with restitution xi.
// Haff's law (Haff 1983; Brilliantov & Poeschel 2004):
//   T(t)/T0 = 1 / (1 + t/tau0)^2,  tau0 = 2 d / ((1 - xi^2) omega0)  [d = 3; 2 in 2D]
// with omega0 the Enskog collision frequency of the initial state; for
// viscoelastic spheres (collision.viscoelastic_speed) T/T0 = (1 + t/tau0)^-5/3
// (systems/edmd/kinetic_theory.hpp).

#include <spdlog/spdlog.h>

#include <cmath>

#include "engine/run/ensemble_keys.hpp"
#include "engine/run/ensemble_series.hpp"
#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "scenarios/output_keys.hpp"
#include "systems/edmd/event_driven_run.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "systems/observables/collisions_per_particle.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/particle_frames.hpp"

namespace granflow::scenarios {
namespace {

template <int D>
void build(Run& run) {
  const Config& c = run.config();
  const auto count = static_cast<double>(c.integer("system.count"));
  const Box<D> box = edmd::box_from<D>(c);
  run.initial_state([&](World& world) {
    edmd::build_gas<D>(world, c, run.seed(), {}, run.preparation("setup"));
    const double energy = total_kinetic_energy<D>(world);
    const double temperature0 = 2.0 / D * energy / count;
    const double eta = theory::packing_fraction<D>(count, c.real("system.radius"), box.volume());
    const double omega0 = theory::collision_frequency<D>(count / box.volume(), 2 * c.real("system.radius"),
                                                         temperature0, c.real("system.mass"), eta);
    run.derive("packing_fraction", eta);
    run.derive("initial_temperature", temperature0);
    run.derive("initial_kinetic_energy", energy);
    run.derive("enskog_collision_frequency", omega0);
    const double viscoelastic = c.real("collision.viscoelastic_speed");
    run.derive("haff_tau0", viscoelastic > 0 ? theory::viscoelastic_haff_time<D>(viscoelastic, temperature0,
                                                                                 c.real("system.mass"), omega0)
                                             : theory::haff_time<D>(c.real("collision.restitution"), omega0));
    run.derive("haff_exponent", viscoelastic > 0 ? 5.0 / 3.0 : 2.0);
  });
  const double energy0 = run.derived("initial_kinetic_energy");
  const double tau0 = run.derived("haff_tau0");
  auto& gas = edmd::add_event_driven_gas<D>(run, box, edmd::CollisionParameters::from(c),
                                            edmd::advance_limits_from(c, run.world().size(), energy0), energy0);
  run.derive("bytes_per_particle", static_cast<double>(gas.bytes_per_particle()));

  const auto outputs = output_times_from(c);
  run.observe<KineticEnergyObserver<D>>(outputs);
  run.observe<CollisionsPerParticleObserver<D>>(outputs);
  add_particle_frames<D>(run, outputs);
  run.stop_at_time(c.real("run.t_stop"));
  // Collisions, the work, grow as ln(1 + t/tau0) in Haff's regime.
  const double t_stop = c.real("run.t_stop");
  if (std::isfinite(tau0) && tau0 > 0)
    run.progress([&gas, tau0, t_stop] { return std::log1p(gas.time() / tau0) / std::log1p(t_stop / tau0); });
  run.at_finish([&gas, &run, tau0](H5mdFile&, const RunOutcome&) {
    spdlog::info("t = {:.6g}: {} collisions, T/T0 = {:.4g}, Haff predicts {:.4g}", gas.time(),
                 gas.statistics().pair_collisions,
                 2.0 / D * gas.kinetic_energy() / static_cast<double>(run.world().size()) /
                     run.derived("initial_temperature"),
                 std::pow(1.0 + gas.time() / tau0, -run.derived("haff_exponent")));
  });
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(haff_cooling, Scenario{
  .name = "haff_cooling",
  .summary = "homogeneous cooling of inelastic hard spheres/disks against Haff's law (EDMD)",
  .default_output = "haff.h5md",
  .keys = [](ConfigSchema& s) {
    edmd::declare_gas_keys(s, {});
    declare_stored_start_keys(s);
    declare_output_time_keys(s, 0.01, 20);
    declare_frame_keys(s, "final", {"none", "final", "all"});
    declare_ensemble_keys(s, 1);
  },
  .build = build_by_dimension<build<2>, build<3>>,
  .adopt = adopt_stored_state_as_one_run,
  .members = ensemble_members,
  .reduce = write_ensemble_series,
  .one_member_runs_plain = true,
})

}  // namespace granflow::scenarios
