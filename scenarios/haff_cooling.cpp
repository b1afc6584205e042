#include "scenarios/haff_cooling.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include "components/clock.hpp"
#include "engine/h5md_file.hpp"
#include "engine/observable_store.hpp"
#include "engine/profiler.hpp"
#include "engine/progress.hpp"
#include "engine/resume_checks.hpp"
#include "engine/run_control.hpp"
#include "engine/schedule.hpp"
#include "scenarios/output_times.hpp"
#include "systems/edmd/edmd_checkpoint.hpp"
#include "systems/edmd/event_driven_step.hpp"
#include "systems/edmd/event_statistics_output.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "systems/observables/collisions_per_particle.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/observable_writer.hpp"
#include "systems/observables/particle_snapshot.hpp"

namespace granflow::scenarios {

const ConfigSchema& haff_cooling_schema() {
  static const ConfigSchema schema = [] {
    ConfigSchema s;
    s.choice("scenario", "haff_cooling", {"haff_cooling"}, "scenario name");
    edmd::declare_gas_keys(s, {});
    s.choice("output.spacing", "log", {"log", "linear"}, "log-spaced or evenly spaced output times")
        .real("output.interval", 1.0, 0.0, std::numeric_limits<double>::infinity(),
              "time between outputs (linear spacing)", true)
        .real("output.first", 0.01, 0.0, std::numeric_limits<double>::infinity(),
              "first output time after t = 0 (log spacing)", true)
        .integer("output.points_per_decade", 20, 1, 1000, "outputs per decade of time (log spacing)")
        .choice("output.positions", "final", {"none", "final", "all"},
                "particle positions and velocities: not at all, at the end, or at every output time")
        .real_or_infinite("output.checkpoint_interval", 600.0, 0.0,
              "wall-clock seconds between checkpoints (written at output times to OUTPUT.checkpoint; 0: at "
              "every output, inf: never); resume with --resume");
    return s;
  }();
  return schema;
}

namespace {

// Whichever stop criterion is closest decides how far the run has come; the
// energy criterion is measured on a log scale, as the gas cools geometrically.
double progress_fraction(double time, double t_stop, std::uint64_t collisions, const edmd::AdvanceLimits& limits,
                         double energy, double energy0) {
  double fraction = time / t_stop;
  if (limits.max_pair_collisions < std::numeric_limits<std::uint64_t>::max())
    fraction = std::max(fraction, static_cast<double>(collisions) / static_cast<double>(limits.max_pair_collisions));
  if (limits.min_kinetic_energy > 0 && energy > 0 && energy0 > limits.min_kinetic_energy)
    fraction = std::max(fraction, std::log(energy0 / energy) / std::log(energy0 / limits.min_kinetic_energy));
  return fraction;
}

template <int D>
int run(const Config& config, const RunOptions& options) {
  const auto count = static_cast<std::size_t>(config.integer("system.count"));
  const std::string output_path = options.output_path.empty() ? "haff.h5" : options.output_path;
  spdlog::info("haff_cooling: {}D, N = {}, seed = {}", D, count, config.integer("run.seed"));

  const double t_stop = config.real("run.t_stop");
  const auto times = config.text("output.spacing") == "log"
                         ? log_output_times(t_stop, config.real("output.first"),
                                            static_cast<int>(config.integer("output.points_per_decade")))
                         : linear_output_times(t_stop, config.real("output.interval"));
  const std::string checkpoint_path = output_path + ".checkpoint";
  // Open the output first, so an unwritable path fails before any work is done.
  H5mdFile file(output_path, "haff_cooling");
  file.write_parameters(config);
  const std::vector<std::string> observables{"kinetic_energy", "temperature", "collisions_per_particle"};
  const std::vector<std::string> derived_names{"packing_fraction", "initial_temperature", "initial_kinetic_energy",
                                               "enskog_collision_frequency", "haff_tau0"};

  World world(count);
  std::map<std::string, double> derived;
  std::optional<edmd::CheckpointContents> resumed;
  if (options.resume) {
    require_checkpoint(checkpoint_path);
    resumed = edmd::read_checkpoint<D>(checkpoint_path, world, observables, derived_names);
    require_same_configuration(checkpoint_path, resumed->configuration, config);
    world.emplace_resource<Box<D>>(edmd::box_from<D>(config));
    derived = resumed->derived;
    spdlog::info("resuming from {} at t = {:.6g}", checkpoint_path, resumed->clock.time);
  } else {
    edmd::build_gas<D>(world, config);
    const auto& box = world.resource<Box<D>>();
    const double eta = theory::packing_fraction<D>(static_cast<double>(count), config.real("system.radius"),
                                                   box.volume());
    const double energy = total_kinetic_energy<D>(world);
    const double temperature0 = 2.0 / D * energy / static_cast<double>(count);
    const double omega0 = theory::collision_frequency<D>(static_cast<double>(count) / box.volume(),
                                                         2 * config.real("system.radius"), temperature0,
                                                         config.real("system.mass"), eta);
    derived = {{"packing_fraction", eta},
               {"initial_temperature", temperature0},
               {"initial_kinetic_energy", energy},
               {"enskog_collision_frequency", omega0},
               {"haff_tau0", theory::haff_time<D>(config.real("collision.restitution"), omega0)}};
  }
  const auto& box = world.resource<Box<D>>();
  const double temperature0 = derived.at("initial_temperature");
  const double tau0 = derived.at("haff_tau0");
  spdlog::info("packing fraction {:.4f}, T0 = {:.6g}, Enskog collision frequency {:.4g}, Haff tau0 = {:.4g}",
               derived.at("packing_fraction"), temperature0, derived.at("enskog_collision_frequency"), tau0);

  edmd::EventDrivenGas<D> gas(world, edmd::collision_parameters_from(config));
  if (resumed)
    gas.restore_state(resumed->engine);
  else
    gas.start(0.0);
  auto& clock = world.emplace_resource<Clock>();
  if (resumed) clock = resumed->clock;
  auto& control = world.emplace_resource<RunControl>();
  auto& store = world.emplace_resource<ObservableStore>();
  for (const auto& name : observables) store.declare(name);

  file.write_box(box.edges(), box.h5md_boundary());
  for (const auto& [name, value] : derived) file.write_attribute("/parameters/derived", name, value);
  file.write_attribute("/parameters/derived", "bytes_per_particle", static_cast<double>(gas.bytes_per_particle()));

  const double energy0 = derived.at("initial_kinetic_energy");
  const edmd::AdvanceLimits limits = edmd::advance_limits_from(config, count, energy0);

  Profiler profiler;
  Schedule schedule(profiler);
  schedule.emplace<edmd::EventDrivenStep<D>>(gas, limits);
  schedule.emplace<KineticEnergyObserver<D>>();
  schedule.emplace<CollisionsPerParticleObserver<D>>(gas);
  auto& writer = schedule.emplace<ObservableWriter>(file, observables);
  if (resumed)
    for (const auto& [name, samples] : resumed->observables)
      for (const auto& sample : samples) writer.append(name, sample);

  const bool all_frames = config.text("output.positions") == "all";
  if (resumed && all_frames)
    spdlog::warn("output.positions = \"all\": frames written before the checkpoint are not carried over");
  const double checkpoint_interval = config.real("output.checkpoint_interval");
  auto last_checkpoint = std::chrono::steady_clock::now();
  Progress progress("haff_cooling", "collisions/s", options.progress);
  for (std::size_t k = resumed ? resumed->next_output : 0; k < times.size(); ++k) {
    control.target_time = times[k];
    schedule.run(world);
    if (all_frames) append_particle_frame<D>(file, world, world.resource<Clock>().step, gas.time());
    progress.update(progress_fraction(gas.time(), t_stop, gas.statistics().pair_collisions, limits,
                                      gas.kinetic_energy(), energy0),
                    static_cast<double>(gas.statistics().pair_collisions));
    if (control.stop) break;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_checkpoint).count() >= checkpoint_interval && k + 1 < times.size()) {
      edmd::write_checkpoint<D>(checkpoint_path, "haff_cooling", config, world, gas, writer, k + 1, derived);
      last_checkpoint = now;
    }
  }
  progress.finish();

  const auto& stats = gas.statistics();
  write_particle_constants(file, world);
  if (config.text("output.positions") == "final")
    append_particle_frame<D>(file, world, world.resource<Clock>().step, gas.time());
  file.write_attribute("/observables", "stop_reason", control.stop ? control.reason : "reached run.t_stop");
  edmd::write_event_statistics(file, stats);
  file.write_profile(profiler.entries());
  file.finish();
  std::filesystem::remove(checkpoint_path);

  spdlog::info("t = {:.6g}: {} collisions ({:.2f} per particle), T/T0 = {:.4g}, Haff predicts {:.4g}", gas.time(),
               stats.pair_collisions, 2.0 * static_cast<double>(stats.pair_collisions) / static_cast<double>(count),
               world.resource<ObservableStore>().slot("temperature").value.at(0) / temperature0,
               theory::haff_temperature_ratio(gas.time(), tau0));
  if (options.profile) fmt::print("{}", profiler.table());
  spdlog::info("wrote {}", output_path);
  if (control.failed) {
    spdlog::error("{}", control.reason);
    return 3;
  }
  if (control.stop) spdlog::info("stopped: {}", control.reason);
  return 0;
}

}  // namespace

int run_haff_cooling(const Config& config, const RunOptions& options) {
  return config.integer("system.dimension") == 2 ? run<2>(config, options) : run<3>(config, options);
}

}  // namespace granflow::scenarios
