// Self-diffusion in the event-driven hard-sphere gas (seed 000 sec. 4.1.4,
// figs. 4.11-4.16): the ensemble MSD of every particle from unwrapped
// positions (periodic image counts), with the mean velocity removed at the
// start, averaged over independent runs (standard error over runs), the
// diffusivity from it (eqs. 4.1-4.2), and optionally the time-averaged MSD
// of a subset sampled at a fixed interval. Every finished run is
// checkpointed (OUTPUT.checkpoint); --resume reruns only the others.
//
// Theory: the Langevin (xi = 1, eq. 2.68) or UDSBM (xi < 1, eq. 2.113)
// MSD with the Enskog D0 of eq. 2.52, gamma0 = T0/(m D0) (eq. 2.55) and Haff's
// tau0 (eq. 2.45), for the measured initial velocity variance: ballistic
// 3 (T0/m) t^2 at first, then 6 D0 t (molecular) or ~6 D0 tau0 ln(1 + t/tau0)
// (granular: ultraslow, logarithmic growth).

#include "scenarios/brownian_edmd.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <optional>

#include "components/clock.hpp"
#include "components/image_count.hpp"
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
#include "systems/edmd/event_driven_step.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/msd.hpp"
#include "systems/observables/multiple_tau_msd.hpp"
#include "systems/sde/sde_theory.hpp"

namespace granflow::scenarios {

const ConfigSchema& brownian_edmd_schema() {
  static const ConfigSchema schema = [] {
    constexpr double inf = std::numeric_limits<double>::infinity();
    ConfigSchema s;
    s.choice("scenario", "brownian_edmd", {"brownian_edmd"}, "scenario name");
    edmd::GasDefaults gas;
    gas.restitution = 1.0;
    edmd::declare_gas_keys(s, gas);
    s.integer("run.runs", 4, 1, 100000, "independent runs (the standard error is taken over them)")
        .real("output.first", 0.001, 0.0, inf, "first output time after t = 0", true)
        .integer("output.points_per_decade", 10, 1, 1000, "log-spaced outputs per decade")
        .integer("msd.time_average_particles", 0, 0, 100000000,
                 "particles of each run whose time-averaged MSD is accumulated (0: none)")
        .real("msd.sample_interval", 0.05, 0.0, inf, "time between the samples of the time-averaged MSD", true)
        .integer("msd.correlator_points", 16, 4, 1024, "lags per level of the multiple-tau correlator");
    return s;
  }();
  return schema;
}

namespace {

struct RunSeries {
  std::vector<double> msd;
  MultipleTauMsd::Result time_average;
  double temperature0 = 0.0;
  bool collapsed = false;
  std::string message;
};

RunSeries one_run(const Config& base, std::int64_t seed, const std::vector<double>& times) {
  constexpr int D = 3;
  Config config = base;
  config.set("run.seed", seed);
  World world;
  edmd::build_gas<D>(world, config);
  world.add_component<ImageCount<D>>().values.assign(world.size(), Eigen::Matrix<std::int32_t, D, 1>::Zero());
  RunSeries out;
  const double energy0 = total_kinetic_energy<D>(world);
  out.temperature0 = 2.0 / D * energy0 / static_cast<double>(world.size());
  edmd::EventDrivenGas<D> gas(world, edmd::collision_parameters_from(config));
  gas.start(0.0);
  world.emplace_resource<Clock>();
  auto& control = world.emplace_resource<RunControl>();
  auto& store = world.emplace_resource<ObservableStore>();
  store.declare("msd");
  Profiler profiler;
  Schedule schedule(profiler);
  schedule.emplace<edmd::EventDrivenStep<D>>(gas, edmd::advance_limits_from(config, world.size(), energy0));
  schedule.emplace<MsdObserver<D>>(world);

  const auto tracked =
      std::min<std::size_t>(world.size(), static_cast<std::size_t>(config.integer("msd.time_average_particles")));
  const double interval = config.real("msd.sample_interval");
  const double t_stop = times.back();
  std::optional<MultipleTauMsd> correlator;
  std::vector<double> buffer(tracked * D);
  const auto sample = [&] {
    // Particles are tracked by id; storage order changes when the engine re-sorts.
    const UnwrappedPositions<D> unwrapped(world);
    for (std::size_t i = 0; i < world.size(); ++i)
      if (const std::uint32_t id = unwrapped.id(i); id < tracked) {
        const Vec<D> u = unwrapped(i);
        for (int a = 0; a < D; ++a) buffer[id * D + a] = u[a];
      }
    correlator->add(buffer.data());
  };
  if (tracked > 0) {
    correlator.emplace(tracked, D, static_cast<std::uint64_t>(t_stop / interval) + 1,
                       static_cast<int>(config.integer("msd.correlator_points")));
    gas.synchronize(0.0);
    sample();
  }
  std::uint64_t next_sample = 1;
  for (std::size_t k = 1; k < times.size() && !control.stop; ++k) {
    // Time-average samples between the MSD output times.
    while (correlator && static_cast<double>(next_sample) * interval < times[k] * (1 - 1e-12)) {
      control.target_time = static_cast<double>(next_sample++) * interval;
      schedule.run(world);
      sample();
    }
    control.target_time = times[k];
    schedule.run(world);
    out.msd.push_back(store.slot("msd").value.at(0));
    if (correlator && std::abs(static_cast<double>(next_sample) * interval - times[k]) <= 1e-12 * times[k]) {
      ++next_sample;
      sample();
    }
  }
  if (control.failed) {
    out.collapsed = true;
    out.message = control.reason;
  }
  if (correlator) out.time_average = correlator->result();
  return out;
}

}  // namespace

// Every finished run, saved after each one finishes (atomically: written as
// .partial and renamed), so an interruption loses only runs in progress.
void save_runs(const RunCheckpoint& checkpoint, const Config& config, const std::vector<RunSeries>& series,
               const std::vector<bool>& done) {
  H5mdFile file(checkpoint.path, "brownian_edmd checkpoint");
  file.write_parameters(config);
  for (std::size_t r = 0; r < series.size(); ++r) {
    if (!done[r] || series[r].collapsed) continue;
    const std::string group = fmt::format("/checkpoint/run{}", r);
    file.write_attribute(group, "initial_temperature", series[r].temperature0);
    file.write_array(group, "msd", series[r].msd);
    file.write_array(group, "lag", series[r].time_average.lag);
    file.write_array(group, "time_averaged_msd", series[r].time_average.msd);
    file.write_array(group, "ergodicity_breaking", series[r].time_average.ergodicity_breaking);
  }
  file.finish();
}

void load_runs(const RunCheckpoint& checkpoint, const Config& config, std::vector<RunSeries>& series,
               std::vector<bool>& done) {
  require_checkpoint(checkpoint.path);
  const H5mdReader reader(checkpoint.path);
  require_same_configuration(checkpoint.path, reader.string_dataset("/parameters/toml"), config);
  for (std::size_t r = 0; r < series.size(); ++r) {
    const std::string group = fmt::format("/checkpoint/run{}", r);
    if (!reader.exists(group)) continue;
    series[r].temperature0 = reader.double_attribute(group, "initial_temperature");
    series[r].msd = reader.doubles(group + "/msd").values;
    series[r].time_average.lag = reader.doubles(group + "/lag").values;
    series[r].time_average.msd = reader.doubles(group + "/time_averaged_msd").values;
    series[r].time_average.ergodicity_breaking = reader.doubles(group + "/ergodicity_breaking").values;
    done[r] = true;
  }
}

EdmdMsdResult measure_edmd_msd(const Config& config, bool show_progress, const RunCheckpoint& checkpoint) {
  if (config.integer("system.dimension") != 3)
    throw ConfigError("brownian_edmd: system.dimension must be 3 (the theory is that of seed 000's 3D gas)");
  if (config.text("system.boundary") != "periodic")
    throw ConfigError("brownian_edmd: system.boundary must be periodic (displacements are unwrapped through images)");
  const double t_stop = config.real("run.t_stop");
  const auto times = log_output_times(t_stop, config.real("output.first"),
                                      static_cast<int>(config.integer("output.points_per_decade")));
  const auto runs = static_cast<std::size_t>(config.integer("run.runs"));
  std::vector<RunSeries> series(runs);
  std::vector<bool> done(runs, false);
  if (checkpoint.resume) {
    load_runs(checkpoint, config, series, done);
    spdlog::info("resuming from {}: {} of {} runs done", checkpoint.path, std::count(done.begin(), done.end(), true),
                 runs);
  }
  Progress progress("brownian_edmd", "runs/s", show_progress);
  std::atomic<std::size_t> finished{static_cast<std::size_t>(std::count(done.begin(), done.end(), true))};
  std::mutex saving;
  // Runs are independent worlds; each is a deterministic function of its seed.
  tbb::parallel_for(std::size_t{0}, runs, [&](std::size_t r) {
    if (done[r]) return;
    // Run 0 keeps run.seed; the others get derived seeds.
    const std::int64_t base = config.integer("run.seed");
    // Non-negative, as run.seed requires.
    const std::int64_t seed =
        r == 0 ? base : static_cast<std::int64_t>(derived_seed(stream::run_seed, static_cast<std::uint64_t>(base), r) >> 1);
    RunSeries result = one_run(config, seed, times);
    std::lock_guard lock(saving);
    series[r] = std::move(result);
    done[r] = true;
    if (!checkpoint.path.empty() && finished + 1 < runs) save_runs(checkpoint, config, series, done);
    progress.update(static_cast<double>(++finished) / static_cast<double>(runs), static_cast<double>(finished));
  });
  progress.finish();
  for (const auto& s : series)
    if (s.collapsed) throw edmd::InelasticCollapse(s.message);

  EdmdMsdResult out;
  double t0 = 0.0;
  for (const auto& s : series) t0 += s.temperature0 / static_cast<double>(runs);
  out.temperature0 = t0;
  const double count = static_cast<double>(config.integer("system.count"));
  out.enskog = sde::model_from_gas(count, config.real("system.radius"), config.real("collision.restitution"), t0,
                                   config.real("system.mass"), std::pow(config.real("system.box_length"), 3));
  std::vector<double> measured(times.begin() + 1, times.end());
  const auto theory = sde::moment_msd(out.enskog, t0 / config.real("system.mass"), measured);
  for (std::size_t k = 0; k < measured.size(); ++k) {
    std::vector<double> samples;
    for (const auto& s : series) samples.push_back(s.msd[k]);
    const auto [mean, error] = mean_and_standard_error(samples);
    out.time.push_back(measured[k]);
    out.msd.push_back(mean);
    out.msd_stderr.push_back(error);
    out.msd_theory.push_back(3.0 * theory[k]);
  }
  // Slope over the last decade (least squares).
  double st = 0, sm = 0, stt = 0, stm = 0, n = 0;
  for (std::size_t k = 0; k < out.time.size(); ++k)
    if (out.time[k] >= 0.1 * t_stop) {
      st += out.time[k];
      sm += out.msd[k];
      stt += out.time[k] * out.time[k];
      stm += out.time[k] * out.msd[k];
      n += 1;
    }
  out.long_time_slope = n >= 2 ? (n * stm - st * sm) / (n * stt - st * st) : std::nan("");
  if (!series.front().time_average.lag.empty()) {
    const double interval = config.real("msd.sample_interval");
    for (std::size_t k = 0; k < series.front().time_average.lag.size(); ++k) {
      double m = 0.0, eb = 0.0;
      for (const auto& s : series) {
        m += s.time_average.msd[k] / static_cast<double>(runs);
        eb += s.time_average.ergodicity_breaking[k] / static_cast<double>(runs);
      }
      out.lag.push_back(series.front().time_average.lag[k] * interval);
      out.time_averaged_msd.push_back(m);
      out.ergodicity_breaking.push_back(eb);
    }
  }
  return out;
}

int run_brownian_edmd(const Config& config, const RunOptions& options) {
  const std::string output_path = options.output_path.empty() ? "brownian_edmd.h5" : options.output_path;
  H5mdFile file(output_path, "brownian_edmd");
  file.write_parameters(config);
  spdlog::info("brownian_edmd: N = {}, xi = {}, {} runs, seed = {}", config.integer("system.count"),
               config.real("collision.restitution"), config.integer("run.runs"), config.integer("run.seed"));
  const RunCheckpoint checkpoint{output_path + ".checkpoint", options.resume};
  EdmdMsdResult r;
  try {
    r = measure_edmd_msd(config, options.progress, checkpoint);
  } catch (const edmd::InelasticCollapse& error) {
    spdlog::error("{}", error.what());
    file.write_attribute("/observables", "stop_reason", error.what());
    file.finish();
    return 3;
  }
  const auto diffusivity = diffusivity_from_msd(r.time, r.msd, 3);
  for (std::size_t k = 0; k < r.time.size(); ++k) {
    file.append_observable("msd", static_cast<std::int64_t>(k), r.time[k], r.msd[k]);
    file.append_observable("msd_stderr", static_cast<std::int64_t>(k), r.time[k], r.msd_stderr[k]);
    file.append_observable("msd_theory", static_cast<std::int64_t>(k), r.time[k], r.msd_theory[k]);
    file.append_observable("diffusivity", static_cast<std::int64_t>(k), r.time[k], diffusivity[k]);
    file.append_observable("diffusivity_theory", static_cast<std::int64_t>(k), r.time[k],
                           r.enskog.diffusivity(r.time[k]));
  }
  for (std::size_t k = 0; k < r.lag.size(); ++k) {
    file.append_observable("time_averaged_msd", static_cast<std::int64_t>(k), r.lag[k], r.time_averaged_msd[k]);
    file.append_observable("ergodicity_breaking", static_cast<std::int64_t>(k), r.lag[k], r.ergodicity_breaking[k]);
  }
  file.write_attribute("/parameters/derived", "initial_temperature", r.temperature0);
  file.write_attribute("/parameters/derived", "enskog_diffusivity0", r.enskog.diffusivity0);
  file.write_attribute("/parameters/derived", "gamma0", r.enskog.gamma0);
  file.write_attribute("/parameters/derived", "haff_tau0", r.enskog.tau0);
  file.write_attribute("/observables", "long_time_slope", r.long_time_slope);
  file.write_attribute("/observables", "stop_reason", "reached run.t_stop");
  file.finish();
  std::filesystem::remove(checkpoint.path);
  spdlog::info("MSD({}) = {:.5g} +- {:.2g} (theory {:.5g}); slope over the last decade {:.4f} = {:.4f} x 6 D0 "
               "(Enskog); wrote {}",
               r.time.back(), r.msd.back(), r.msd_stderr.back(), r.msd_theory.back(), r.long_time_slope,
               r.long_time_slope / (6 * r.enskog.diffusivity0), output_path);
  return 0;
}

}  // namespace granflow::scenarios
