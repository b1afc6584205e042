// Shear viscosity of the stochastic rotation dynamics fluid: a periodic box
// of cells sheared through Lees-Edwards planes, kept at its temperature by a
// global thermostat; the measured kinetic and collisional viscosities against
// the theory of Kikuchi et al. 2003 (systems/srd/srd_theory.hpp). The run
// starts from the linear profile the planes drive, samples the stress every
// step after `viscosity.warmup_steps` and reports the averages so far.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "engine/core/units.hpp"
#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/srd/shear_viscosity.hpp"
#include "systems/srd/srd_fields.hpp"
#include "systems/srd/srd_frames.hpp"
#include "systems/srd/srd_setup.hpp"
#include "systems/srd/srd_state_observer.hpp"
#include "systems/srd/srd_theory.hpp"
#include "systems/srd/srd_watchdog.hpp"

namespace granflow::scenarios {
namespace {

template <int D>
void build(Run& run) {
  const Config& c = run.config();
  if (c.real("shear.rate") <= 0.0)
    throw ConfigError("srd_viscosity measures the response to shear: shear.rate must be > 0 (it is 0)");
  if (c.integer("viscosity.warmup_steps") >= c.integer("run.steps"))
    throw ConfigError(fmt::format("viscosity.warmup_steps = {} leaves no step to sample before run.steps = {}",
                                  c.integer("viscosity.warmup_steps"), c.integer("run.steps")));
  srd::add_srd_fluid<D>(run);
  srd::add_srd_fields<D>(run, srd::cells_from<D>(c));
  const double alpha = c.real("srd.rotation_angle") * std::numbers::pi / 180.0;
  const auto n0 = static_cast<double>(c.integer("srd.particles_per_cell"));
  const double dt = c.real("srd.time_step");
  const double temperature = c.real("thermostat.temperature") > 0 ? c.real("thermostat.temperature") : c.real("srd.temperature");
  run.derive("viscosity_kinetic_theory", srd::kinetic_viscosity(D, n0, alpha, temperature, dt));
  run.derive("viscosity_collisional_theory", srd::collisional_viscosity(D, n0, alpha, dt));
  const auto every = c.integer("output.every_steps");
  const auto warmup = c.integer("viscosity.warmup_steps");
  const auto cells = srd::cells_from<D>(c);
  auto sums = std::make_shared<srd::ShearStress>(cells[1], dt, c.integer("viscosity.block_steps"));
  run.keep("shear_stress", *sums);
  run.observe<srd::ShearStressSampler<D>>(std::make_shared<EverySteps>(1, warmup + 1), sums);
  const auto outputs = std::make_shared<EverySteps>(every);
  srd::add_srd_frames<D>(run, outputs);
  srd::observe_state<D>(run, outputs);
  run.observe<srd::ShearViscosityObserver<D>>(outputs, sums);
  run.at_finish([sums, &run, n = static_cast<double>(run.world().size())](H5mdFile& file, const RunOutcome&) {
    const double rate = sums->measured_shear_rate();
    const auto nu = sums->viscosities(rate, n);
    file.write_attribute("/observables", "viscosity_kinetic_mean", nu.kinetic);
    file.write_attribute("/observables", "viscosity_kinetic_stderr", nu.kinetic_error);
    file.write_attribute("/observables", "viscosity_collisional_mean", nu.collisional);
    file.write_attribute("/observables", "viscosity_collisional_stderr", nu.collisional_error);
    file.write_attribute("/observables", "shear_rate_mean", rate);
    // Beside the measurements, so that a sweep's summary can collect them.
    file.write_attribute("/observables", "viscosity_kinetic_theory", run.derived("viscosity_kinetic_theory"));
    file.write_attribute("/observables", "viscosity_collisional_theory", run.derived("viscosity_collisional_theory"));
    spdlog::info("shear rate {:.5g}: nu_kin = {:.5g} +- {:.2g} (theory {:.5g}), nu_coll = {:.5g} +- {:.2g} (theory {:.5g})",
                 rate, nu.kinetic, nu.kinetic_error, run.derived("viscosity_kinetic_theory"), nu.collisional,
                 nu.collisional_error, run.derived("viscosity_collisional_theory"));
  });
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(srd_viscosity, Scenario{
  .name = "srd_viscosity",
  .summary = "shear viscosity of the SRD fluid (Lees-Edwards shear, thermostat) against Kikuchi et al. 2003",
  .default_output = "srd_viscosity.h5md",
  .keys = [](ConfigSchema& s) {
    srd::SrdDefaults d;
    d.dimension = 2;
    d.cells = {32, 32};
    d.particles_per_cell = 5;
    d.angle = 120.0;
    d.dt = 1.0;
    d.temperature = 0.8;
    d.shear_rate = 2.0 / 32.0;
    d.thermostat = 0.8;
    d.steps = 20000;
    srd::declare_srd_keys(s, d);
    declare_frame_keys(s, "none");
    s.integer("output.every_steps", 500, 1, 1000000000, "steps between outputs")
        .integer("viscosity.warmup_steps", 2000, 0, 1000000000, "steps before the stress is sampled")
        .integer("viscosity.block_steps", 200, 1, 1000000000, "steps per block of the standard errors");
  },
  .build = build_by_dimension<build<2>, build<3>>,
  .adopt = adopt_stored_state,
})

}  // namespace granflow::scenarios
