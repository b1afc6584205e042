// Shear viscosity of the stochastic rotation dynamics fluid: a periodic box
// of cells sheared through Lees-Edwards planes, kept at its temperature by a
// global thermostat; the measured kinetic and collisional viscosities against
// the theory of Kikuchi et al. 2003 (systems/srd/srd_theory.hpp). The run
// starts from the linear profile the planes drive, samples the stress every
// step after `viscosity.warmup_steps` and reports the averages so far.
// Granular SRD (srd.restitution < 1, no thermostat) reaches the temperature
// where viscous heating and dissipation balance; its kinetic viscosity is
// compared with the granular theory at the measured temperature
// (systems/srd/granular_shear_theory.hpp), and the density, velocity and
// temperature profiles across the gradient, with the width and contrast of a
// shear band, are written at every output.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "engine/core/units.hpp"
#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/srd/granular_shear_theory.hpp"
#include "systems/srd/shear_viscosity.hpp"
#include "systems/srd/srd_profiles.hpp"
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
  const srd::GranularShearParameters granular{D,  srd::dissipation_from(c), n0, alpha, dt, c.real("srd.restitution"),
                                              c.real("srd.diameter")};
  const bool dissipative = c.real("srd.restitution") < 1.0 && c.real("srd.diameter") > 0.0;
  if (dissipative && c.real("thermostat.temperature") == 0.0) {
    const double steady = srd::steady_shear_temperature(granular, c.real("shear.rate"), run.derived("viscosity_collisional_theory"));
    run.derive("temperature_steady_theory", steady);
    if (std::isfinite(steady) && (c.real("srd.temperature") > 3 * steady || c.real("srd.temperature") < steady / 3))
      spdlog::warn("granular shear at rate {:.4g} settles near kT = {:.4g} (heating = dissipation); srd.temperature = "
                   "{:.4g} starts far from it, and a fluid started too cold may collapse into a band before it heats",
                   c.real("shear.rate"), steady, c.real("srd.temperature"));
  }
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
  // From the first step: a band forms early, before the stress is sampled.
  // Ten samples per output resolve a band (a layer holds hundreds of
  // particles); sampling every step would add a serial pass over the
  // particles to each step (3.7 % of the instructions at every tenth step).
  srd::add_layer_profiles<D>(run, cells, 1, 0, every, 0, true, std::max<std::int64_t>(1, every / 10));
  run.at_finish([sums, &run, granular, dissipative](H5mdFile& file, const RunOutcome&) {
    const double n = sums->particles();
    const double rate = sums->measured_shear_rate();
    const auto nu = sums->viscosities(rate, n);
    const auto [measured_t, measured_t_error] = sums->temperature_yy();
    file.write_attribute("/observables", "temperature_yy_mean", measured_t);
    file.write_attribute("/observables", "temperature_yy_stderr", measured_t_error);
    // Both theories at the measured temperature: the granular one reduces to the elastic one at eps = 1.
    const double elastic = srd::kinetic_viscosity(D, granular.n0, granular.alpha, measured_t, granular.dt);
    const double kinetic_granular = srd::granular_kinetic_viscosity(granular, measured_t);
    file.write_attribute("/observables", "viscosity_elastic_theory", elastic);
    file.write_attribute("/observables", "viscosity_granular_theory", kinetic_granular);
    file.write_attribute("/observables", "viscosity_granular_deviation", (nu.kinetic - kinetic_granular) / kinetic_granular);
    file.write_attribute("/observables", "viscosity_elastic_deviation", (nu.kinetic - elastic) / elastic);
    if (dissipative) {
      const double steady = srd::steady_shear_temperature(granular, rate, run.derived("viscosity_collisional_theory"));
      bool clamped = false;
      const double eps = srd::effective_restitution(granular.restitution, granular.diameter, granular.n0, measured_t,
                                                    granular.dt, clamped);
      file.write_attribute("/observables", "temperature_steady_theory_measured_rate", steady);
      file.write_attribute("/observables", "effective_restitution_mean", eps);
      spdlog::info("granular: kT_yy = {:.5g} +- {:.2g} (heating = dissipation at the measured rate: {:.5g}), eps_eff = "
                   "{:.4f}; nu_kin theory at kT_yy: granular {:.5g} ({:+.2f} %), elastic {:.5g}",
                   measured_t, measured_t_error, steady, eps, kinetic_granular,
                   100 * (nu.kinetic - kinetic_granular) / kinetic_granular, elastic);
    }
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
