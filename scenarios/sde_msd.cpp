// Mean squared displacement of Langevin dynamics (`langevin_msd`, the
// molecular gas) and of underdamped scaled Brownian motion (`udsbm_msd`, the
// granular gas), seed 000 sec. 4.2, figs. 4.17-4.23: an ensemble of
// independent particles started at one point, with gamma0, D0 (and tau0)
// those of the hard-sphere gas N = 1000, r = 0.025, L = 1, T0 = 2/3 (eqs.
// 2.45, 2.52, 2.55), or given directly. Several independent runs give the
// standard error of the ensemble MSD; the time-averaged MSD (eq. 2.115) of a
// subset of particles is accumulated on the fly by a multiple-tau
// correlator, with the ergodicity-breaking parameter. Each finished run is
// checkpointed (OUTPUT.checkpoint); --resume continues after the last one.
//
// Theory: the exact second-moment equations for the initial velocity
// variance used (systems/sde/sde_theory.hpp), which are eq. 2.68 (Langevin)
// and eq. 2.113 (UDSBM) for a stationary start.

#include "scenarios/sde_msd.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/h5md_file.hpp"
#include "engine/h5md_reader.hpp"
#include "engine/observable_store.hpp"
#include "engine/profiler.hpp"
#include "engine/progress.hpp"
#include "engine/resume_checks.hpp"
#include "engine/rng.hpp"
#include "engine/run_control.hpp"
#include "engine/sample_statistics.hpp"
#include "engine/schedule.hpp"
#include "engine/stream_ids.hpp"
#include "scenarios/output_times.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/observables/msd.hpp"
#include "systems/observables/multiple_tau_msd.hpp"
#include "systems/sde/sde_step.hpp"
#include "systems/sde/sde_theory.hpp"

namespace granflow::scenarios {

namespace {

ConfigSchema sde_schema(const std::string& name, bool scaled) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  ConfigSchema s;
  s.choice("scenario", name, {name}, "scenario name")
      .integer("system.dimension", 3, 1, 3, "number of Cartesian components per particle")
      .integer("system.count", 1000, 1, 100000000, "particles per run (independent, all start at the origin)")
      .choice("sde.parameters", "gas", {"gas", "direct"},
              "gas: gamma0, D0, tau0 of the hard-sphere gas gas.* (seed 000 eqs. 2.45, 2.52, 2.55); direct: sde.*")
      .real("sde.gamma0", 10.0, 0.0, inf, "friction coefficient gamma0 (sde.parameters = direct)", true)
      .real("sde.diffusivity0", 0.05, 0.0, inf, "diffusivity D0 (sde.parameters = direct)", true)
      .real("gas.count", 1000.0, 0.0, inf, "N of the gas the parameters come from", true)
      .real("gas.radius", 0.025, 0.0, inf, "particle radius r of that gas", true)
      .real("gas.box_length", 1.0, 0.0, inf, "edge of its cubic box", true)
      .real("gas.temperature", 2.0 / 3.0, 0.0, inf, "its initial temperature T0 (2/3: speed sqrt(2))", true)
      .real("gas.mass", 1.0, 0.0, inf, "particle mass m", true)
      .choice("initial.velocity", "stationary", {"stationary", "fixed_speed"},
              "stationary: Gaussian with the variance the noise sustains at t = 0; fixed_speed: |v| = "
              "initial.speed in random directions (seed 000's choice)")
      .real("initial.speed", std::sqrt(2.0), 0.0, inf, "initial speed (fixed_speed)")
      .real("run.t_stop", 100.0, 0.0, inf, "stop time", true)
      .real("run.dt", 0.01, 0.0, inf, "time step", true)
      .choice("run.scheme", "exact_ou", {"exact_ou", "euler_maruyama"},
              "exact_ou: exact Ornstein-Uhlenbeck velocity update between half drifts (BAOAB-style); "
              "euler_maruyama: seed 000 eqs. 2.92 / 2.110")
      .integer("run.runs", 4, 1, 100000, "independent runs (the standard error is taken over them)")
      .integer("run.seed", 1, 0, std::numeric_limits<std::int64_t>::max(), "seed of every random stream")
      .real("output.first", 0.01, 0.0, inf, "first output time after t = 0", true)
      .integer("output.points_per_decade", 10, 1, 1000, "log-spaced outputs per decade")
      .integer("msd.time_average_particles", 1000, 0, 100000000,
               "particles of each run whose time-averaged MSD is accumulated (0: none)")
      .integer("msd.correlator_points", 16, 4, 1024, "lags per level of the multiple-tau correlator");
  if (scaled) {
    s.real("gas.restitution", 0.8, 0.0, 1.0, "restitution xi of that gas (xi < 1: UDSBM; sets tau0)")
        .real("sde.tau0", 1.0, 0.0, inf, "decay time tau0 of gamma and D (sde.parameters = direct)", true);
  }
  return s;
}

}  // namespace

const ConfigSchema& langevin_msd_schema() {
  static const ConfigSchema schema = sde_schema("langevin_msd", false);
  return schema;
}
const ConfigSchema& udsbm_msd_schema() {
  static const ConfigSchema schema = sde_schema("udsbm_msd", true);
  return schema;
}

sde::SdeModel sde_model_from(const Config& config) {
  const bool scaled = config.text("scenario") == "udsbm_msd";
  sde::SdeModel model;
  if (config.text("sde.parameters") == "direct") {
    model.gamma0 = config.real("sde.gamma0");
    model.diffusivity0 = config.real("sde.diffusivity0");
    if (scaled) model.tau0 = config.real("sde.tau0");
  } else {
    const double xi = scaled ? config.real("gas.restitution") : 1.0;
    model = sde::model_from_gas(config.real("gas.count"), config.real("gas.radius"), xi,
                                config.real("gas.temperature"), config.real("gas.mass"),
                                std::pow(config.real("gas.box_length"), 3));
    if (!scaled) model.tau0 = std::numeric_limits<double>::infinity();
  }
  if (model.scaled() && std::abs(model.gamma0 * model.tau0 - 1.0) < 1e-9)
    throw ConfigError("gamma0 * tau0 = 1 is the degenerate case of UDSBM's MSD; choose other parameters");
  return model;
}

namespace {

// Saves the finished runs' series (atomically: written as .partial, renamed).
void save_runs(const RunCheckpoint& checkpoint, const Config& config, std::size_t finished,
               const std::vector<std::vector<double>>& msd, const std::vector<double>& lags,
               const std::vector<std::vector<double>>& tamsd, const std::vector<std::vector<double>>& breaking) {
  H5mdFile file(checkpoint.path, config.text("scenario") + " checkpoint");
  file.write_parameters(config);
  file.write_attribute("/checkpoint", "finished_runs", static_cast<double>(finished));
  file.write_array("/checkpoint", "lags", lags);
  for (std::size_t r = 0; r < finished; ++r) {
    const std::string group = fmt::format("/checkpoint/run{}", r);
    file.write_array(group, "msd", msd[r]);
    file.write_array(group, "time_averaged_msd", tamsd[r]);
    file.write_array(group, "ergodicity_breaking", breaking[r]);
  }
  file.finish();
}

std::size_t load_runs(const RunCheckpoint& checkpoint, const Config& config, std::vector<std::vector<double>>& msd,
                      std::vector<double>& lags, std::vector<std::vector<double>>& tamsd,
                      std::vector<std::vector<double>>& breaking) {
  require_checkpoint(checkpoint.path);
  const H5mdReader reader(checkpoint.path);
  require_same_configuration(checkpoint.path, reader.string_dataset("/parameters/toml"), config);
  const auto finished = static_cast<std::size_t>(reader.double_attribute("/checkpoint", "finished_runs"));
  lags = reader.doubles("/checkpoint/lags").values;
  for (std::size_t r = 0; r < finished && r < msd.size(); ++r) {
    const std::string group = fmt::format("/checkpoint/run{}", r);
    msd[r] = reader.doubles(group + "/msd").values;
    tamsd[r] = reader.doubles(group + "/time_averaged_msd").values;
    breaking[r] = reader.doubles(group + "/ergodicity_breaking").values;
  }
  return std::min(finished, msd.size());
}

template <int D>
SdeMsdResult measure(const Config& config, bool show_progress, const RunCheckpoint& checkpoint) {
  const sde::SdeModel model = sde_model_from(config);
  const auto count = static_cast<std::size_t>(config.integer("system.count"));
  const double dt = config.real("run.dt");
  const double t_stop = config.real("run.t_stop");
  const auto total_steps = static_cast<std::int64_t>(std::llround(t_stop / dt));
  if (total_steps < 1 || total_steps > 1e12)
    throw ConfigError(fmt::format("run.t_stop / run.dt = {:.3g} steps: allowed is 1 to 1e12", t_stop / dt));
  // Output times rounded to whole steps.
  std::vector<std::int64_t> steps;
  for (double t : log_output_times(t_stop, config.real("output.first"),
                                   static_cast<int>(config.integer("output.points_per_decade")))) {
    const auto s = std::min<std::int64_t>(total_steps, std::llround(t / dt));
    if (s > 0 && (steps.empty() || s > steps.back())) steps.push_back(s);
  }
  const auto runs = static_cast<std::size_t>(config.integer("run.runs"));
  const auto tracked = std::min<std::size_t>(count, static_cast<std::size_t>(config.integer("msd.time_average_particles")));
  const sde::Scheme scheme =
      config.text("run.scheme") == "euler_maruyama" ? sde::Scheme::euler_maruyama : sde::Scheme::exact_ou;
  if (scheme == sde::Scheme::euler_maruyama && model.gamma0 * dt >= 2.0)
    throw ConfigError(fmt::format("run.dt = {} with gamma0 = {:.4g}: Euler-Maruyama's velocity update diverges for "
                                  "gamma0 * dt >= 2 (here {:.3g}); lower run.dt or use run.scheme = \"exact_ou\"",
                                  dt, model.gamma0, model.gamma0 * dt));
  if (model.gamma0 * dt > 0.5)
    spdlog::warn("gamma0 * dt = {:.3g}: the step does not resolve the velocity relaxation time 1/gamma0; the MSD "
                 "is only right at times of many steps",
                 model.gamma0 * dt);
  const bool stationary = config.text("initial.velocity") == "stationary";
  const double speed = config.real("initial.speed");
  const double v2 = stationary ? model.stationary_velocity_variance(0.0) : speed * speed / D;

  std::vector<std::vector<double>> msd(runs), tamsd(runs), breaking(runs);
  std::vector<double> lags;
  Progress progress(config.text("scenario"), "particle-steps/s", show_progress);
  std::size_t first_run = 0;
  if (checkpoint.resume) {
    first_run = load_runs(checkpoint, config, msd, lags, tamsd, breaking);
    spdlog::info("resuming from {}: {} of {} runs done", checkpoint.path, first_run, runs);
  }
  for (std::size_t r = first_run; r < runs; ++r) {
    // Run 0 keeps run.seed; the others get derived seeds.
    const auto base = static_cast<std::uint64_t>(config.integer("run.seed"));
    const std::uint64_t seed = r == 0 ? base : derived_seed(stream::run_seed, base, r);
    World world(count);
    world.add_component<Position<D>>().values.assign(count, Vec<D>::Zero());
    auto& velocity = world.add_component<Velocity<D>>();
    for (std::size_t i = 0; i < count; ++i) {
      Philox random(stream::sde_initial, seed, 0, i);
      if (stationary)
        for (int a = 0; a < D; ++a) velocity[i][a] = std::sqrt(v2) * random.normal();
      else
        velocity[i] = speed * random_direction<D>(random);
    }
    world.emplace_resource<Clock>();
    auto& control = world.emplace_resource<RunControl>();
    auto& store = world.emplace_resource<ObservableStore>();
    store.declare("msd");

    std::optional<MultipleTauMsd> correlator;
    if (tracked > 0)
      correlator.emplace(tracked, D, static_cast<std::uint64_t>(total_steps),
                         static_cast<int>(config.integer("msd.correlator_points")));
    const auto feed = [&](std::int64_t) { correlator->add(world.component<Position<D>>()[0].data()); };
    if (correlator) feed(0);
    Profiler profiler;
    Schedule schedule(profiler);
    schedule.emplace<sde::SdeAdvance<D>>(model, scheme, dt, seed,
                                          correlator ? std::function<void(std::int64_t)>(feed) : nullptr);
    schedule.emplace<MsdObserver<D>>(world);
    for (std::int64_t s : steps) {
      control.target_time = static_cast<double>(s) * dt;
      schedule.run(world);
      msd[r].push_back(store.slot("msd").value.at(0));
      progress.update((static_cast<double>(r) + static_cast<double>(s) / static_cast<double>(total_steps)) /
                          static_cast<double>(runs),
                      static_cast<double>(count) * static_cast<double>(r * total_steps + s));
    }
    if (correlator) {
      const auto result = correlator->result();
      lags = result.lag;
      tamsd[r] = result.msd;
      breaking[r] = result.ergodicity_breaking;
    }
    if (!checkpoint.path.empty() && r + 1 < runs) save_runs(checkpoint, config, r + 1, msd, lags, tamsd, breaking);
  }
  progress.finish();

  // Mean and standard error over runs of the k-th value of every run's series.
  const auto mean_and_error = [](const std::vector<std::vector<double>>& series, std::size_t k) {
    std::vector<double> samples;
    for (const auto& s : series) samples.push_back(s[k]);
    const auto [mean, error] = mean_and_standard_error(samples);
    return std::pair{mean, error};
  };
  SdeMsdResult out;
  out.initial_velocity_variance = v2;
  for (std::int64_t s : steps) out.time.push_back(static_cast<double>(s) * dt);
  const auto theory = sde::moment_msd(model, v2, out.time);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const auto [mean, error] = mean_and_error(msd, k);
    out.msd.push_back(mean);
    out.msd_stderr.push_back(error);
    out.msd_theory.push_back(D * theory[k]);
  }
  for (std::size_t k = 0; k < lags.size(); ++k) {
    const auto [mean, error] = mean_and_error(tamsd, k);
    out.lag.push_back(lags[k] * dt);
    out.time_averaged_msd.push_back(mean);
    out.time_averaged_msd_stderr.push_back(error);
    out.ergodicity_breaking.push_back(mean_and_error(breaking, k).first);
  }
  return out;
}

}  // namespace

SdeMsdResult measure_sde_msd(const Config& config, bool progress, const RunCheckpoint& checkpoint) {
  switch (config.integer("system.dimension")) {
    case 1: return measure<1>(config, progress, checkpoint);
    case 2: return measure<2>(config, progress, checkpoint);
    default: return measure<3>(config, progress, checkpoint);
  }
}

int run_sde_msd(const Config& config, const RunOptions& options) {
  const std::string scenario = config.text("scenario");
  const std::string output_path = options.output_path.empty() ? scenario + ".h5" : options.output_path;
  H5mdFile file(output_path, scenario);
  file.write_parameters(config);
  const sde::SdeModel model = sde_model_from(config);
  spdlog::info("{}: {}D, {} runs x {} particles, gamma0 = {:.5g}, D0 = {:.5g}, tau0 = {:.5g}, dt = {}, scheme {}, "
               "seed = {}",
               scenario, config.integer("system.dimension"), config.integer("run.runs"),
               config.integer("system.count"), model.gamma0, model.diffusivity0, model.tau0, config.real("run.dt"),
               config.text("run.scheme"), config.integer("run.seed"));
  file.write_attribute("/parameters/derived", "gamma0", model.gamma0);
  file.write_attribute("/parameters/derived", "diffusivity0", model.diffusivity0);
  file.write_attribute("/parameters/derived", "tau0", model.tau0);
  const RunCheckpoint checkpoint{output_path + ".checkpoint", options.resume};
  const auto result = measure_sde_msd(config, options.progress, checkpoint);
  file.write_attribute("/parameters/derived", "initial_velocity_variance", result.initial_velocity_variance);
  const auto dimension = static_cast<int>(config.integer("system.dimension"));
  const auto diffusivity = diffusivity_from_msd(result.time, result.msd, dimension);
  const auto diffusivity_theory = diffusivity_from_msd(result.time, result.msd_theory, dimension);
  const double dt = config.real("run.dt");
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
  file.write_attribute("/observables", "stop_reason", "reached run.t_stop");
  file.finish();
  std::filesystem::remove(checkpoint.path);
  spdlog::info("MSD({}) = {:.5g} +- {:.2g} (theory {:.5g}); largest deviation from theory {:.2f} standard errors; "
               "wrote {}",
               result.time.back(), result.msd.back(), result.msd_stderr.back(), result.msd_theory.back(), worst,
               output_path);
  return 0;
}

}  // namespace granflow::scenarios
