// Mean squared displacement of Langevin dynamics (`langevin_msd`, the
// molecular gas) and of underdamped scaled Brownian motion (`udsbm_msd`, the
// granular gas; Bodrova et al. 2016): an ensemble of
// independent particles started at one point, with gamma0, D0 (and tau0)
// those of the hard-sphere gas N = 1000, r = 0.025, L = 1, T0 = 2/3 (Enskog
// theory, systems/sde/sde_theory.hpp), or given directly. Several independent runs give the
// standard error of the ensemble MSD; the time-averaged MSD (Metzler et al. 2014) of a
// subset of particles is accumulated on the fly by a multiple-tau
// correlator, with the ergodicity-breaking parameter. Each finished run is
// checkpointed (OUTPUT.checkpoint); --resume continues after the last one.
//
// Theory: the exact second-moment equations for the initial velocity
// variance used (systems/sde/sde_theory.hpp), which are the closed forms of
// Langevin dynamics and of UDSBM (Bodrova et al. 2016) for a stationary start.

#include "scenarios/sde_msd.hpp"

#include <spdlog/spdlog.h>

#include <tbb/task_arena.h>

#include "engine/core/memory_check.hpp"
#include "engine/run/ensemble_keys.hpp"
#include "engine/run/run.hpp"
#include "engine/run/runner.hpp"
#include "systems/observables/msd.hpp"
#include "systems/observables/particle_frames.hpp"
#include "systems/sde/sde_ensemble.hpp"
#include "systems/sde/sde_frames.hpp"
#include "systems/sde/sde_step.hpp"
#include "systems/sde/sde_watchdog.hpp"

namespace granflow::scenarios {

namespace {

void declare_keys(ConfigSchema& s, bool scaled) {
  sde::declare_ensemble_keys(s);
  sde::declare_sde_model_keys(s, scaled);
  sde::declare_sde_step_keys(s);
  declare_ensemble_keys(s, 4);
  declare_msd_keys(s, MsdDefaults{1000, 0.0});
  declare_frame_keys(s, "none");
}

template <int D>
void build(Run& run) {
  const Config& c = run.config();
  const sde::SdeModel model = sde::sde_model_from(c);
  const auto s = sde::ensemble_stepping_from(c, model, D);
  const auto count = static_cast<std::size_t>(c.integer("system.count"));
  // Position, velocity and MSD origin per particle, for every run going at once.
  const auto at_once = std::min<std::size_t>(ensemble_members(c), tbb::this_task_arena::max_concurrency());
  require_memory(fmt::format("system.count = {} with {} runs at a time", count, at_once),
                 3.0 * 8.0 * D * static_cast<double>(count) * static_cast<double>(at_once) +
                     sde::sde_frame_bytes(c, s.output_steps.size()));
  run.initial_state([&](World& world) { sde::start_at_origin<D>(world, c, count, s, run.seed()); });
  run.step<sde::SdeAdvance<D>>(model, s.scheme, s.dt, run.seed());
  if (run.member() == 0) sde::warn_about_step(s, model);
  const auto outputs = std::make_shared<AtSteps>(s.output_steps);
  run.keep("msd", run.observe<MsdObserver<D>>(outputs, run.world()));
  run.observe<sde::SdeWatch>(outputs, s.unstable_until, model.gamma0 * s.dt);
  sde::add_sde_frames<D>(run, s.output_steps);
  add_time_averaged_msd<D>(run, std::make_shared<EverySteps>(1), static_cast<std::uint64_t>(s.total_steps));
  run.stop_at_step(s.total_steps);
  const auto particles = static_cast<double>(count);
  run.rate("particle-steps/s", [&run, particles] { return particles * static_cast<double>(run.clock().step); });
}

void write(const Config& config, const SdeMsdResult& result, H5mdFile& file) {
  const sde::SdeModel model = sde::sde_model_from(config);
  file.write_attribute("/parameters/derived", "gamma0", model.gamma0);
  file.write_attribute("/parameters/derived", "diffusivity0", model.diffusivity0);
  file.write_attribute("/parameters/derived", "tau0", model.tau0);
  file.write_attribute("/parameters/derived", "initial_velocity_variance", result.initial_velocity_variance);
  const double dt = config.real("run.dt");
  write_ensemble_msd(file, result, static_cast<int>(config.integer("system.dimension")),
                     [dt](std::size_t, double t) { return std::llround(t / dt); });
  const double worst = largest_deviation_in_standard_errors(result);
  file.write_attribute("/observables", "largest_deviation_in_standard_errors", worst);
  spdlog::info("MSD({}) = {:.5g} +- {:.2g} (theory {:.5g}); largest deviation from theory {:.2f} standard errors",
               result.time.back(), result.msd.back(), result.msd_stderr.back(), result.msd_theory.back(), worst);
}

Scenario sde_scenario(const std::string& name, bool scaled, const std::string& summary) {
  return Scenario{
      .name = name,
      .summary = summary,
      .default_output = name + ".h5md",
      .keys = [scaled](ConfigSchema& s) { declare_keys(s, scaled); },
      .build = build_by_dimension<build<1>, build<2>, build<3>>,
      .members = ensemble_members,
      .reduce =
          [](const EnsembleResults& r, H5mdFile& file) {
            write(r.config, reduce_sde_msd(r), file);
            sde::write_sde_frames(r.config, r.members.front().history, file);
          },
  };
}

const Scenario langevin_msd = sde_scenario(
    "langevin_msd", false, "ensemble and time-averaged MSD of underdamped Langevin particles (SDE; ergodic)");
const Scenario udsbm_msd = sde_scenario(
    "udsbm_msd", true, "ensemble and time-averaged MSD of underdamped scaled Brownian motion (SDE; not ergodic)");

}  // namespace

SdeMsdResult reduce_sde_msd(const EnsembleResults& results) {
  const Config& config = results.config;
  const sde::SdeModel model = sde::sde_model_from(config);
  const auto dimension = static_cast<int>(config.integer("system.dimension"));
  const auto s = sde::ensemble_stepping_from(config, model, dimension);
  std::vector<double> time, theory;
  for (std::int64_t step : s.output_steps) time.push_back(static_cast<double>(step) * s.dt);
  for (double per_axis : sde::moment_msd(model, s.initial_velocity_variance, time)) theory.push_back(dimension * per_axis);
  SdeMsdResult out{reduce_ensemble_msd(results, std::move(time), std::move(theory), s.dt)};
  out.initial_velocity_variance = s.initial_velocity_variance;
  return out;
}

SdeMsdResult measure_sde_msd(const Config& config) {
  return reduce_sde_msd(simulate_ensemble(config.text("scenario") == "udsbm_msd" ? udsbm_msd : langevin_msd, config));
}

GRANFLOW_REGISTER_SCENARIO(langevin_msd, langevin_msd)
GRANFLOW_REGISTER_SCENARIO(udsbm_msd, udsbm_msd)

}  // namespace granflow::scenarios
