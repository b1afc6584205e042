#include "scenarios/speed_study.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "components/clock.hpp"
#include "components/species.hpp"
#include "engine/h5md_file.hpp"
#include "engine/observable_store.hpp"
#include "engine/profiler.hpp"
#include "engine/progress.hpp"
#include "engine/run_control.hpp"
#include "engine/schedule.hpp"
#include "scenarios/speed_output.hpp"
#include "systems/edmd/event_driven_step.hpp"
#include "systems/edmd/event_statistics_output.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/observables/collisions_per_particle.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/observable_writer.hpp"
#include "engine/particle_output.hpp"
#include "systems/observables/species_kinetic_energy.hpp"

namespace granflow::scenarios {

void declare_speed_study_keys(ConfigSchema& s, const SamplingDefaults& d) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  s.real("sampling.equilibration_collisions", d.equilibration_collisions, 0.0, 1e6,
         "collisions per particle before the first speed snapshot")
      .integer("sampling.snapshots", d.snapshots, 1, 100000, "speed snapshots gathered into the histograms")
      .real("sampling.collisions_between", d.collisions_between, 0.0, 1e6,
            "collisions per particle between snapshots (>> 1 makes them nearly independent)", true)
      .integer("output.bins", 50, 2, 100000, "bins of the speed histograms")
      .real("output.interval", d.output_interval, 0.0, inf, "time between outputs of the kinetic energies", true)
      .choice("output.positions", "final", {"none", "final"}, "particle positions and velocities at the end");
}

void declare_speed_study_gas_keys(ConfigSchema& s) {
  edmd::GasDefaults gas;
  gas.dimension = 2;
  gas.count = 4000;
  gas.radius = 0.003;
  gas.boundary = "reflecting";
  gas.velocity = "fixed_speed";
  gas.restitution = 1.0;
  gas.t_stop = 100.0;
  gas.remove_mean_velocity = false;  // walls do not conserve momentum; keep the one-speed start exact
  edmd::declare_gas_keys(s, gas);
}

namespace {

double max_of(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

template <int D>
int run(const Config& config, const RunOptions& options, const SpeedStudy& study) {
  const auto count = static_cast<std::size_t>(config.integer("system.count"));
  const std::size_t species_count = study.species_names.size();
  const std::string output_path = options.output_path.empty() ? study.scenario + ".h5" : options.output_path;
  spdlog::info("{}: {}D, N = {}, seed = {}", study.scenario, D, count, config.integer("run.seed"));
  H5mdFile file(output_path, study.scenario);
  file.write_parameters(config);

  World world(count);
  edmd::build_gas<D>(world, config, study.customize);
  const auto& box = world.resource<Box<D>>();
  file.write_box(box.edges(), box.h5md_boundary());

  // The mass of each species, for Maxwell-Boltzmann at that species' temperature.
  std::vector<double> species_mass(species_count, config.real("system.mass"));
  if (species_count > 1)
    for (std::size_t i = 0; i < count; ++i)
      species_mass[world.component<Species>()[i]] = world.component<Mass>()[i];

  SpeedSamples initial(species_count);
  initial.add<D>(world);
  const double energy0 = total_kinetic_energy<D>(world);

  edmd::EventDrivenGas<D> gas(world, edmd::collision_parameters_from(config));
  gas.start(0.0);
  world.emplace_resource<Clock>();
  auto& control = world.emplace_resource<RunControl>();
  auto& store = world.emplace_resource<ObservableStore>();
  std::vector<std::string> observables{"kinetic_energy", "temperature", "collisions_per_particle"};
  if (species_count > 1) observables.push_back(SpeciesKineticEnergyObserver<D>::observable);
  for (const auto& name : observables) store.declare(name);

  const edmd::AdvanceLimits limits = edmd::advance_limits_from(config, count, energy0);
  const double max_cpp = config.real("run.max_collisions_per_particle");

  Profiler profiler;
  Schedule schedule(profiler);
  schedule.emplace<edmd::EventDrivenStep<D>>(gas, limits);
  schedule.emplace<KineticEnergyObserver<D>>();
  schedule.emplace<CollisionsPerParticleObserver<D>>(gas);
  if (species_count > 1) schedule.emplace<SpeciesKineticEnergyObserver<D>>(species_count);
  schedule.emplace<ObservableWriter>(file, observables);
  // The state at t = 0 is the first point of every time series.
  control.target_time = 0.0;
  schedule.run(world);

  const double t_stop = config.real("run.t_stop");
  const double interval = config.real("output.interval");
  const double first_sample = config.real("sampling.equilibration_collisions");
  const double between = config.real("sampling.collisions_between");
  const auto snapshots = static_cast<std::size_t>(config.integer("sampling.snapshots"));
  const auto collisions_for = [&](double per_particle) {
    return static_cast<std::uint64_t>(std::ceil(per_particle * static_cast<double>(count) / 2));
  };
  SpeedSamples sampled(species_count);
  std::size_t taken = 0;
  std::uint64_t output_index = 1;
  Progress progress(study.scenario, "collisions/s", options.progress);
  while (!control.stop) {
    const double next_output = std::min(t_stop, static_cast<double>(output_index) * interval);
    control.target_time = next_output;
    control.pause_at_pair_collisions = taken < snapshots ? collisions_for(first_sample + taken * between)
                                                         : std::numeric_limits<std::uint64_t>::max();
    schedule.run(world);
    if (taken < snapshots && gas.statistics().pair_collisions >= control.pause_at_pair_collisions) {
      sampled.add<D>(world);
      ++taken;
    } else {
      ++output_index;
    }
    const double cpp = 2.0 * static_cast<double>(gas.statistics().pair_collisions) / static_cast<double>(count);
    const double planned = std::max(first_sample + (snapshots - 1) * between, std::isfinite(max_cpp) ? max_cpp : 0.0);
    progress.update(std::max(gas.time() / t_stop, cpp / planned), static_cast<double>(gas.statistics().pair_collisions));
    if (gas.time() >= t_stop) break;
    if (taken == snapshots && !std::isfinite(max_cpp)) break;  // nothing left to wait for
  }
  progress.finish();
  if (taken < snapshots)
    spdlog::warn("{}: only {} of {} speed snapshots were taken before the run stopped ({}); raise run.t_stop or "
                 "run.max_collisions_per_particle",
                 study.scenario, taken, snapshots, control.stop ? control.reason : "reached run.t_stop");

  // Histograms share one range so initial and equilibrium can be overlaid.
  const int bins = static_cast<int>(config.integer("output.bins"));
  const double v_max = 1.05 * std::max(max_of(initial.all_speeds()), max_of(sampled.all_speeds()));
  const double mass = config.real("system.mass");
  write_speed_histogram<D>(file, "speed_histogram_initial", initial.all_speeds(), mass, v_max, bins);
  if (species_count == 1) {
    const auto report = write_speed_histogram<D>(file, "speed_histogram", sampled.all_speeds(), mass, v_max, bins);
    spdlog::info("{} speeds: mean {:.4f} (Maxwell-Boltzmann {:.4f}), rms {:.4f} ({:.4f}), most probable {:.4f} "
                 "({:.4f}); chi-square {:.1f} (0.999 critical {:.1f})",
                 report.measured.samples, report.measured.mean, theory::mean_speed<D>(report.temperature, mass),
                 report.measured.rms, theory::rms_speed<D>(report.temperature, mass), report.measured.most_probable,
                 theory::most_probable_speed<D>(report.temperature, mass), report.chi_square,
                 report.chi_square_critical);
  } else {
    for (std::size_t s = 0; s < species_count; ++s) {
      const auto& label = study.species_names[s];
      write_speed_histogram<D>(file, "speed_histogram_initial_" + label, initial.speeds(s), species_mass[s], v_max,
                               bins);
      const auto report = write_speed_histogram<D>(file, "speed_histogram_" + label, sampled.speeds(s),
                                                   species_mass[s], v_max, bins);
      spdlog::info("{} (m = {:g}): mean speed {:.4f}, mean kinetic energy {:.5f}", label, species_mass[s],
                   report.measured.mean, 0.5 * species_mass[s] * report.measured.rms * report.measured.rms);
    }
  }
  file.write_attribute("/observables", "speed_snapshots", static_cast<double>(taken));

  const auto& stats = gas.statistics();
  write_particle_constants(file, world);
  if (config.text("output.positions") == "final")
    append_particle_frame<D>(file, world, world.resource<Clock>().step, gas.time());
  file.write_attribute("/observables", "stop_reason", control.stop ? control.reason : "reached the last snapshot or run.t_stop");
  edmd::write_event_statistics(file, stats);
  file.write_profile(profiler.entries());
  file.finish();
  if (options.profile) fmt::print("{}", profiler.table());
  spdlog::info("wrote {} (t = {:.4g}, {:.1f} collisions per particle)", output_path, gas.time(),
               2.0 * static_cast<double>(stats.pair_collisions) / static_cast<double>(count));
  if (control.failed) {
    spdlog::error("{}", control.reason);
    return 3;
  }
  return 0;
}

}  // namespace

int run_speed_study(const Config& config, const RunOptions& options, const SpeedStudy& study) {
  return config.integer("system.dimension") == 2 ? run<2>(config, options, study) : run<3>(config, options, study);
}

}  // namespace granflow::scenarios
