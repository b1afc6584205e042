// Free cooling of the granular SRD fluid in a periodic box: the temperature
// against Haff's law T0 / (1 + t/tau)^2 with the mean-field tau of
// systems/srd/srd_theory.hpp, the convective energy, density fluctuations and
// Mach number that show the onset of clustering (at lower restitution and
// angle, e.g. srd.restitution = 0.98, srd.rotation_angle = 10), and the
// velocity distribution in c = v / v_T with its Sonine coefficients.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "engine/core/output_times.hpp"
#include "engine/core/units.hpp"
#include "engine/run/ensemble_keys.hpp"
#include "engine/run/ensemble_series.hpp"
#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/srd/clustering.hpp"
#include "systems/srd/cooling_exponent.hpp"
#include "systems/srd/srd_fields.hpp"
#include "systems/srd/srd_frames.hpp"
#include "systems/srd/srd_setup.hpp"
#include "systems/srd/srd_state_observer.hpp"
#include "systems/srd/srd_theory.hpp"
#include "systems/srd/srd_watchdog.hpp"
#include "systems/srd/velocity_distribution.hpp"

namespace granflow::scenarios {
namespace {

void describe_velocity_distribution(H5mdFile& file, std::size_t bins) {
  const std::string group = "/observables/velocity_distribution";
  file.write_attribute(group, "variable", "c = |v - <v>| / sqrt(2 T_g / m), T_g the granular temperature");
  file.write_attribute(group, "c_max", srd::reduced_speed_max);
  file.write_attribute(group, "bins", static_cast<double>(bins));
}

// The cooling exponent after the transition (systems/srd/cooling_exponent.hpp)
// of the thermal temperature, as attributes of /observables.
void write_cooling_exponent(H5mdFile& file, const std::vector<double>& time, const std::vector<double>& temperature,
                            const std::vector<double>& mach) {
  const auto fit = srd::cooling_after_transition(time, temperature, mach);
  file.write_attribute("/observables", "transition_time", fit.transition_time);
  file.write_attribute("/observables", "cooling_exponent", fit.exponent);
  file.write_attribute("/observables", "cooling_exponent_stderr", fit.exponent_error);
  if (std::isnan(fit.transition_time))
    spdlog::info("the global Mach number stayed below 1: no transition to inhomogeneous cooling, no exponent fitted");
  else
    spdlog::info("Mach number 1 at t = {:.4g}; after it T ~ t^{:.3f} (+- {:.2g}, {} outputs)", fit.transition_time,
                 fit.exponent, fit.exponent_error, fit.points);
}

std::vector<double> values_of(const std::vector<ObservableSample>& samples) {
  std::vector<double> out;
  for (const auto& sample : samples) out.push_back(sample.value.at(0));
  return out;
}
std::vector<double> times_of(const std::vector<ObservableSample>& samples) {
  std::vector<double> out;
  for (const auto& sample : samples) out.push_back(sample.time);
  return out;
}

template <int D>
void build(Run& run) {
  const Config& c = run.config();
  srd::add_srd_fluid<D>(run);
  srd::add_srd_fields<D>(run, srd::cells_from<D>(c));
  const auto n0 = static_cast<double>(c.integer("srd.particles_per_cell"));
  const double tau = srd::gsrd_haff_time(D, srd::dissipation_from(c), c.real("srd.restitution"), c.real("srd.diameter"),
                                         n0, c.real("srd.temperature"));
  run.derive("haff_tau", tau);
  run.derive("initial_temperature", c.real("srd.temperature"));
  const auto outputs =
      std::make_shared<AtSteps>(log_output_steps(static_cast<double>(c.integer("run.steps")), 1.0,
                                                static_cast<int>(c.integer("output.points_per_decade")), 1.0));
  srd::add_srd_frames<D>(run, outputs);
  srd::observe_state<D>(run, outputs);
  const auto bins = static_cast<std::size_t>(c.integer("output.distribution_bins"));
  run.observe<srd::VelocityDistributionObserver<D>>(outputs, bins);
  run.observe<srd::ClusteringObserver<D>>(outputs, srd::cells_from<D>(c), n0, c.real("clusters.threshold"));
  run.at_finish([bins](H5mdFile& file, const RunOutcome&) { describe_velocity_distribution(file, bins); });
  run.at_finish([&run](H5mdFile& file, const RunOutcome&) {
    const auto& history = run.recorder().history();
    write_cooling_exponent(file, times_of(history.at("temperature")), values_of(history.at("temperature")),
                           values_of(history.at("mach_number")));
  });
  run.at_finish([&run, tau](H5mdFile&, const RunOutcome&) {
    const double t = run.clock().time;
    spdlog::info("t = {:.4g} ({} steps): Haff's law predicts T/T0 = {:.4g}", t, run.clock().step,
                 1.0 / ((1.0 + t / tau) * (1.0 + t / tau)));
  });
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(gsrd_cooling, Scenario{
  .name = "gsrd_cooling",
  .summary = "free cooling of granular SRD against Haff's law; clustering at low restitution",
  .default_output = "gsrd_cooling.h5md",
  .keys = [](ConfigSchema& s) {
    srd::SrdDefaults d;
    d.dimension = 3;
    d.cells = {32, 32, 32};
    d.particles_per_cell = 10;
    d.angle = 20.0;
    d.dt = 0.01;
    d.temperature = 100.0;
    d.restitution = 0.995;
    d.diameter = 1.0;
    d.steps = 20000;
    srd::declare_srd_keys(s, d);
    declare_frame_keys(s, "none");
    s.integer("output.points_per_decade", 20, 1, 1000, "outputs per decade of steps");
    s.integer("output.distribution_bins", 40, 2, 100000, "bins of velocity_distribution in c = |v - <v>| / v_T, over [0, 4)");
    s.real("clusters.threshold", 2.0, 0.0, 1e9, "a cell belongs to a cluster above this many times n0 particles");
    s.unit("clusters.threshold", unit::none);
    declare_ensemble_keys(s, 1);
  },
  .build = build_by_dimension<build<2>, build<3>>,
  .adopt = adopt_stored_state,
  .members = ensemble_members,
  .reduce = [](const EnsembleResults& results, H5mdFile& file) {
    write_ensemble_series(results, file);
    describe_velocity_distribution(file, static_cast<std::size_t>(results.config.integer("output.distribution_bins")));
    const auto& first = results.members.front().history;
    std::vector<double> temperature, mach;
    const std::size_t count = std::min(common_samples(results, "temperature"), common_samples(results, "mach_number"));
    for (std::size_t k = 0; k < count; ++k) {
      temperature.push_back(mean_and_standard_error(member_values(results, "temperature", k)).mean);
      mach.push_back(mean_and_standard_error(member_values(results, "mach_number", k)).mean);
    }
    std::vector<double> time = times_of(first.at("temperature"));
    time.resize(count);
    write_cooling_exponent(file, time, temperature, mach);
  },
  .one_member_runs_plain = true,
})

}  // namespace granflow::scenarios
