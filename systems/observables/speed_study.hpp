#pragma once
// The run shared by `speed_distribution` and `mixture`: a hard-disk (sphere)
// gas started at one speed, observed at short, even time intervals (kinetic
// energy, per species for a mixture), whose speeds are sampled in several
// snapshots many collisions per particle apart once it has equilibrated
// (such snapshots are nearly independent samples), then histogrammed per
// species against Maxwell-Boltzmann.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "components/species.hpp"
#include "engine/core/output_times.hpp"
#include "engine/run/run.hpp"
#include "systems/edmd/event_driven_run.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/observables/collisions_per_particle.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/particle_frames.hpp"
#include "systems/observables/species_kinetic_energy.hpp"
#include "systems/observables/speed_histogram_output.hpp"
#include "systems/observables/speed_samples.hpp"
#include "systems/observables/speed_snapshot_observer.hpp"

namespace granflow {

struct SamplingDefaults {
  double equilibration_collisions = 20.0;
  std::int64_t snapshots = 10;
  double collisions_between = 10.0;
  double output_interval = 0.01;
};

inline void declare_speed_study_keys(ConfigSchema& s, const SamplingDefaults& d) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  edmd::GasDefaults gas;  // 4000 disks (r = 0.003) at one speed in a unit box with reflecting walls, elastic
  gas.dimension = 2;
  gas.count = 4000;
  gas.radius = 0.003;
  gas.boundary = "reflecting";
  gas.velocity = "fixed_speed";
  gas.restitution = 1.0;
  gas.remove_mean_velocity = false;  // walls do not conserve momentum; keep the one-speed start exact
  edmd::declare_gas_keys(s, gas);
  declare_stored_start_keys(s);
  s.real("sampling.equilibration_collisions", d.equilibration_collisions, 0.0, 1e6,
         "collisions per particle before the first speed snapshot")
      .integer("sampling.snapshots", d.snapshots, 1, 100000, "speed snapshots gathered into the histograms")
      .real("sampling.collisions_between", d.collisions_between, 0.0, 1e6,
            "collisions per particle between snapshots (>> 1 makes them nearly independent)", true)
      .integer("output.bins", 50, 2, 100000, "bins of the speed histograms")
      .real("output.interval", d.output_interval, 0.0, inf, "time between outputs of the kinetic energies", true);
  declare_frame_keys(s, "final", {"none", "final"});
}

inline double largest(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

// `species_names`: one label per species (a single species needs no Species component);
// `customize` sets masses, radii and species before placement.
template <int D>
void build_speed_study(Run& run, const std::vector<std::string>& species_names,
                       const std::function<void(World&)>& customize) {
  const Config& c = run.config();
  const std::size_t species_count = species_names.size();
  const Box<D> box = edmd::box_from<D>(c);
  auto initial = std::make_shared<SpeedSnapshotObserver<D>>(species_count);
  run.initial_state([&](World& world) {
    edmd::build_gas<D>(world, c, run.seed(), customize,
                       run.preparation("setup"));
    initial->run(world);
    run.derive("initial_kinetic_energy", total_kinetic_energy<D>(world));
  });
  run.keep("initial_speeds", *initial);
  const double energy0 = run.derived("initial_kinetic_energy");
  const auto count = run.world().size();
  auto& gas = edmd::add_event_driven_gas<D>(run, box, edmd::CollisionParameters::from(c),
                                            edmd::advance_limits_from(c, count, energy0), energy0);

  // Kinetic energies every output.interval, and at every snapshot.
  const double t_stop = c.real("run.t_stop");
  const double first = c.real("sampling.equilibration_collisions");
  const double between = c.real("sampling.collisions_between");
  const auto snapshots = static_cast<std::size_t>(c.integer("sampling.snapshots"));
  std::vector<std::int64_t> snapshot_steps;
  for (std::size_t k = 0; k < snapshots; ++k)
    snapshot_steps.push_back(static_cast<std::int64_t>(
        std::ceil((first + static_cast<double>(k) * between) * static_cast<double>(count) / 2)));
  check_output_count(t_stop, c.real("output.interval"));
  const TriggerPtr outputs = std::make_shared<EveryTime>(c.real("output.interval"), t_stop);
  const TriggerPtr at_snapshots = std::make_shared<AtSteps>(snapshot_steps);
  const TriggerPtr observed = std::make_shared<AnyOf>(std::vector<TriggerPtr>{outputs, at_snapshots});
  run.observe<KineticEnergyObserver<D>>(observed);
  run.observe<CollisionsPerParticleObserver<D>>(observed);
  if (species_count > 1) run.observe<SpeciesKineticEnergyObserver<D>>(observed, species_count);
  auto& sampled = run.observe<SpeedSnapshotObserver<D>>(at_snapshots, species_count);
  run.keep("speed_snapshots", sampled);
  add_particle_frames<D>(run, outputs);
  run.stop_at_time(t_stop);
  run.finished_reason("reached the last snapshot or run.t_stop");
  const bool collision_limit = std::isfinite(c.real("run.max_collisions_per_particle"));
  run.stop_when([&sampled, snapshots, collision_limit]() -> std::optional<std::string> {
    if (sampled.taken() == snapshots && !collision_limit) return "reached the last snapshot or run.t_stop";
    return std::nullopt;
  });
  const double planned = static_cast<double>(snapshot_steps.back());
  run.progress([&gas, planned] { return static_cast<double>(gas.statistics().pair_collisions) / planned; });

  run.at_finish([&c, &gas, &run, initial, &sampled, species_names, snapshots](H5mdFile& file, const RunOutcome& outcome) {
    const std::size_t species = species_names.size();
    if (sampled.taken() < snapshots)
      spdlog::warn("only {} of {} speed snapshots were taken before the run stopped ({}); raise run.t_stop or "
                   "run.max_collisions_per_particle",
                   sampled.taken(), snapshots, outcome.reason);
    // The mass of each species, for Maxwell-Boltzmann at that species' temperature.
    const World& world = run.world();
    std::vector<double> species_mass(species, c.real("system.mass"));
    if (species > 1)
      for (std::size_t i = 0; i < world.size(); ++i)
        species_mass[world.component<Species>()[i]] = world.component<Mass>()[i];
    // Histograms share one range so initial and equilibrium can be overlaid.
    const int bins = static_cast<int>(c.integer("output.bins"));
    const double v_max =
        1.05 * std::max(largest(initial->samples().all_speeds()), largest(sampled.samples().all_speeds()));
    const double mass = c.real("system.mass");
    write_speed_histogram<D>(file, "speed_histogram_initial", initial->samples().all_speeds(), mass, v_max, bins);
    if (species == 1) {
      const auto report =
          write_speed_histogram<D>(file, "speed_histogram", sampled.samples().all_speeds(), mass, v_max, bins);
      spdlog::info("{} speeds: mean {:.4f} (Maxwell-Boltzmann {:.4f}), rms {:.4f} ({:.4f}); chi-square {:.1f} "
                   "(0.999 critical {:.1f})",
                   report.measured.samples, report.measured.mean, theory::mean_speed<D>(report.temperature, mass),
                   report.measured.rms, theory::rms_speed<D>(report.temperature, mass), report.chi_square,
                   report.chi_square_critical);
    } else {
      // The columns of kinetic_energy_by_species, in species order.
      std::string columns;
      for (std::size_t s = 0; s < species; ++s) {
        if (s) columns += ' ';
        columns += species_names[s];
      }
      file.write_attribute("/observables/kinetic_energy_by_species", "columns", columns);
      for (std::size_t s = 0; s < species; ++s) {
        write_speed_histogram<D>(file, "speed_histogram_initial_" + species_names[s], initial->samples().speeds(s),
                                 species_mass[s], v_max, bins);
        const auto report = write_speed_histogram<D>(file, "speed_histogram_" + species_names[s],
                                                     sampled.samples().speeds(s), species_mass[s], v_max, bins);
        spdlog::info("{} (m = {:g}): mean speed {:.4f}, mean kinetic energy {:.5f}", species_names[s],
                     species_mass[s], report.measured.mean,
                     0.5 * species_mass[s] * report.measured.rms * report.measured.rms);
      }
    }
    file.write_attribute("/observables", "speed_snapshots", static_cast<double>(sampled.taken()));
    spdlog::info("t = {:.4g}, {:.1f} collisions per particle", gas.time(),
                 2.0 * static_cast<double>(gas.statistics().pair_collisions) / static_cast<double>(world.size()));
  });
}

}  // namespace granflow
