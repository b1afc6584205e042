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

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <tbb/task_arena.h>

#include <cmath>

#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/ensemble_keys.hpp"
#include "engine/h5md_file.hpp"
#include "engine/memory_check.hpp"
#include "engine/output_times.hpp"
#include "engine/rng.hpp"
#include "engine/run.hpp"
#include "engine/runner.hpp"
#include "engine/sample_statistics.hpp"
#include "engine/stream_ids.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/observables/msd.hpp"
#include "systems/observables/particle_frames.hpp"
#include "systems/observables/time_averaged_msd.hpp"
#include "systems/sde/sde_frames.hpp"
#include "systems/sde/sde_parameters.hpp"
#include "systems/sde/sde_step.hpp"
#include "systems/sde/sde_theory.hpp"

namespace granflow::scenarios {

namespace {

void declare_keys(ConfigSchema& s, bool scaled) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  s.integer("system.dimension", 3, 1, 3, "number of Cartesian components per particle")
      .integer("system.count", 1000, 1, 100000000, "particles per run (independent, all start at the origin)")
      .choice("initial.velocity", "stationary", {"stationary", "fixed_speed"},
              "stationary: Gaussian with the variance the noise sustains at t = 0; fixed_speed: |v| = "
              "initial.speed in random directions (as the hard-sphere gas starts)")
      .real("initial.speed", std::sqrt(2.0), 0.0, inf, "initial speed (fixed_speed)")
      .real("run.t_stop", 100.0, 0.0, inf, "stop time", true)
      .real("output.first", 0.01, 0.0, inf, "first output time after t = 0", true)
      .integer("output.points_per_decade", 10, 1, 1000, "log-spaced outputs per decade");
  sde::declare_sde_model_keys(s, scaled);
  sde::declare_sde_step_keys(s);
  declare_ensemble_keys(s, 4);
  declare_msd_keys(s, MsdDefaults{1000, 0.0});
  declare_frame_keys(s, "none");
}

struct Stepping {
  double dt;
  std::int64_t total_steps;
  std::vector<std::int64_t> output_steps;  // log-spaced output times rounded to whole steps
  sde::Scheme scheme;
  double initial_velocity_variance;  // per component
};

Stepping stepping_from(const Config& config, const sde::SdeModel& model, int dimension) {
  Stepping s;
  s.dt = config.real("run.dt");
  const double t_stop = config.real("run.t_stop");
  s.total_steps = static_cast<std::int64_t>(std::llround(t_stop / s.dt));
  if (s.total_steps < 1 || s.total_steps > 1e12)
    throw ConfigError(fmt::format("run.t_stop / run.dt = {:.3g} steps: allowed is 1 to 1e12", t_stop / s.dt));
  for (double t : log_output_times(t_stop, config.real("output.first"),
                                   static_cast<int>(config.integer("output.points_per_decade")))) {
    const auto step = std::min<std::int64_t>(s.total_steps, std::llround(t / s.dt));
    if (step > 0 && (s.output_steps.empty() || step > s.output_steps.back())) s.output_steps.push_back(step);
  }
  s.scheme = sde::scheme_from(config);
  if (s.scheme == sde::Scheme::euler_maruyama && model.gamma0 * s.dt >= 2.0)
    throw ConfigError(fmt::format("run.dt = {} with gamma0 = {:.4g}: Euler-Maruyama's velocity update diverges for "
                                  "gamma0 * dt >= 2 (here {:.3g}); lower run.dt or use run.scheme = \"exact_ou\"",
                                  s.dt, model.gamma0, model.gamma0 * s.dt));
  if (model.scaled() && sde::moment_msd_steps(model, t_stop) > 1e10)
    throw ConfigError(fmt::format("the UDSBM theory curve would need {:.3g} integration steps (gamma0 * tau0 = {:.3g}); "
                                  "lower gamma0 or tau0 (sde.* or gas.*) or run.t_stop",
                                  sde::moment_msd_steps(model, t_stop), model.gamma0 * model.tau0));
  const double speed = config.real("initial.speed");
  s.initial_velocity_variance = config.text("initial.velocity") == "stationary"
                                    ? model.stationary_velocity_variance(0.0)
                                    : speed * speed / dimension;
  return s;
}

template <int D>
void build(Run& run) {
  const Config& c = run.config();
  const sde::SdeModel model = sde::sde_model_from(c);
  const Stepping s = stepping_from(c, model, D);
  if (run.member() == 0 && model.gamma0 * s.dt > 0.5)
    spdlog::warn("gamma0 * dt = {:.3g}: the step does not resolve the velocity relaxation time 1/gamma0; the MSD "
                 "is only right at times of many steps",
                 model.gamma0 * s.dt);
  const auto count = static_cast<std::size_t>(c.integer("system.count"));
  // Position, velocity and MSD origin per particle, for every run going at once.
  const auto at_once = std::min<std::size_t>(ensemble_members(c), tbb::this_task_arena::max_concurrency());
  require_memory(fmt::format("system.count = {} with {} runs at a time", count, at_once),
                 3.0 * 8.0 * D * static_cast<double>(count) * static_cast<double>(at_once) +
                     sde::sde_frame_bytes(c, s.output_steps.size()));
  const bool stationary = c.text("initial.velocity") == "stationary";
  run.initial_state([&](World& world) {
    world.resize(count);
    world.add_component<Position<D>>().values.assign(count, Vec<D>::Zero());
    auto& velocity = world.add_component<Velocity<D>>();
    for (std::size_t i = 0; i < count; ++i) {
      Philox random(stream::sde_initial, run.seed(), 0, i);
      if (stationary)
        for (int a = 0; a < D; ++a) velocity[i][a] = std::sqrt(s.initial_velocity_variance) * random.normal();
      else
        velocity[i] = c.real("initial.speed") * random_direction<D>(random);
    }
  });
  run.step<sde::SdeAdvance<D>>(model, s.scheme, s.dt, run.seed());
  run.keep("msd", run.observe<MsdObserver<D>>(std::make_shared<AtSteps>(s.output_steps), run.world()));
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
  const auto dimension = static_cast<int>(config.integer("system.dimension"));
  const auto diffusivity = diffusivity_from_msd(result.time, result.msd, dimension);
  const auto diffusivity_theory = diffusivity_from_msd(result.time, result.msd_theory, dimension);
  const double dt = config.real("run.dt");
  declare_msd_series_units(file);
  for (std::size_t k = 0; k < result.time.size(); ++k) {
    const auto step = std::llround(result.time[k] / dt);
    file.append_observable("msd", step, result.time[k], result.msd[k]);
    file.append_observable("msd_stderr", step, result.time[k], result.msd_stderr[k]);
    file.append_observable("msd_theory", step, result.time[k], result.msd_theory[k]);
    file.append_observable("diffusivity", step, result.time[k], diffusivity[k]);
    file.append_observable("diffusivity_theory", step, result.time[k], diffusivity_theory[k]);
  }
  // Lags of the time average are stored as the `time` of these series.
  for (std::size_t k = 0; k < result.lag.size(); ++k) {
    const auto step = std::llround(result.lag[k] / dt);
    file.append_observable("time_averaged_msd", step, result.lag[k], result.time_averaged_msd[k]);
    file.append_observable("time_averaged_msd_stderr", step, result.lag[k], result.time_averaged_msd_stderr[k]);
    file.append_observable("ergodicity_breaking", step, result.lag[k], result.ergodicity_breaking[k]);
  }
  double worst = 0.0;
  for (std::size_t k = 0; k < result.time.size(); ++k)
    if (result.msd_stderr[k] > 0)
      worst = std::max(worst, std::abs(result.msd[k] - result.msd_theory[k]) / result.msd_stderr[k]);
  file.write_attribute("/observables", "largest_deviation_in_standard_errors", worst);
  spdlog::info("MSD({}) = {:.5g} +- {:.2g} (theory {:.5g}); largest deviation from theory {:.2f} standard errors",
               result.time.back(), result.msd.back(), result.msd_stderr.back(), result.msd_theory.back(), worst);
}

void build_any(Run& run) {
  switch (run.config().integer("system.dimension")) {
    case 1: return build<1>(run);
    case 2: return build<2>(run);
    default: return build<3>(run);
  }
}

Scenario sde_scenario(const std::string& name, bool scaled, const std::string& summary) {
  return Scenario{
      .name = name,
      .summary = summary,
      .default_output = name + ".h5md",
      .keys = [scaled](ConfigSchema& s) { declare_keys(s, scaled); },
      .build = build_any,
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
  const Stepping s = stepping_from(config, model, dimension);
  SdeMsdResult out;
  out.initial_velocity_variance = s.initial_velocity_variance;
  for (std::int64_t step : s.output_steps) out.time.push_back(static_cast<double>(step) * s.dt);
  const auto theory = sde::moment_msd(model, s.initial_velocity_variance, out.time);
  for (std::size_t k = 0; k < out.time.size(); ++k) {
    const auto [mean, error] = mean_and_standard_error(member_values(results, "msd", k));
    out.msd.push_back(mean);
    out.msd_stderr.push_back(error);
    out.msd_theory.push_back(dimension * theory[k]);
  }
  const auto& history = results.members.back().history;
  if (!history.count("time_averaged_msd_lag")) return out;
  const auto& lags = history.at("time_averaged_msd_lag").back().value;
  for (std::size_t k = 0; k < lags.size(); ++k) {
    const auto [mean, error] = mean_and_standard_error(member_values(results, "time_averaged_msd", 0, k));
    out.lag.push_back(lags[k] * s.dt);
    out.time_averaged_msd.push_back(mean);
    out.time_averaged_msd_stderr.push_back(error);
    out.ergodicity_breaking.push_back(mean_and_standard_error(member_values(results, "ergodicity_breaking", 0, k)).mean);
  }
  return out;
}

SdeMsdResult measure_sde_msd(const Config& config) {
  return reduce_sde_msd(simulate_ensemble(config.text("scenario") == "udsbm_msd" ? udsbm_msd : langevin_msd, config));
}

GRANFLOW_REGISTER_SCENARIO(langevin_msd, langevin_msd)
GRANFLOW_REGISTER_SCENARIO(udsbm_msd, udsbm_msd)

}  // namespace granflow::scenarios
