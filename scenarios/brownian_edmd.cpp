// Self-diffusion in the event-driven hard-sphere gas : the ensemble MSD of every particle from unwrapped
// positions (periodic image counts), with the mean velocity removed at the
// start, averaged over independent runs (standard error over runs), the
// diffusivity from it (D = dMSD/dt / 2d), and optionally the time-averaged MSD
// of a subset sampled at a fixed interval. Every finished run is
// checkpointed (OUTPUT.checkpoint); --resume reruns only the others.
//
// Theory: the Langevin (xi = 1) or UDSBM (xi < 1; Bodrova et al. 2016)
// MSD with the Enskog D0, gamma0 = T0/(m D0) and Haff's
// tau0, for the measured initial velocity variance: ballistic
// 3 (T0/m) t^2 at first, then 6 D0 t (molecular) or ~6 D0 tau0 ln(1 + t/tau0)
// (granular: ultraslow, logarithmic growth).

#include "scenarios/brownian_edmd.hpp"

#include <spdlog/spdlog.h>

#include <cmath>

#include "components/image_count.hpp"
#include "engine/core/output_times.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/ensemble_keys.hpp"
#include "engine/run/run.hpp"
#include "engine/run/runner.hpp"
#include "systems/edmd/event_driven_run.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/least_squares.hpp"
#include "systems/observables/msd.hpp"
#include "systems/observables/time_averaged_msd.hpp"
#include "systems/sde/sde_theory.hpp"

namespace granflow::scenarios {

namespace {

void build(Run& run) {
  constexpr int D = 3;
  const Config& c = run.config();
  if (c.integer("system.dimension") != 3 || c.text("system.boundary") != "periodic")
    throw ConfigError("brownian_edmd needs system.dimension = 3 (the theory is that of the 3D gas) and "
                      "system.boundary = \"periodic\" (displacements are unwrapped through images)");
  run.initial_state([&](World& world) {
    edmd::build_gas<D>(world, c, run.seed(), {}, run.preparation("setup"));
    world.add_component<ImageCount<D>>().values.assign(world.size(), Eigen::Matrix<std::int32_t, D, 1>::Zero());
    const double energy = total_kinetic_energy<D>(world);
    run.derive("initial_kinetic_energy", energy);
    run.derive("initial_temperature", 2.0 / D * energy / static_cast<double>(world.size()));
  });
  const double energy0 = run.derived("initial_kinetic_energy");
  edmd::add_event_driven_gas<D>(run, edmd::box_from<D>(c), edmd::CollisionParameters::from(c),
                                edmd::advance_limits_from(c, run.world().size(), energy0), energy0);
  auto times = log_output_times(c.real("run.t_stop"), c.real("output.first"),
                                static_cast<int>(c.integer("output.points_per_decade")));
  times.erase(times.begin());  // the MSD is 0 at t = 0
  run.keep("msd", run.observe<MsdObserver<D>>(std::make_shared<AtTimes>(times), run.world()));
  const double interval = c.real("msd.sample_interval");
  if (c.integer("msd.time_average_particles") > 0) check_output_count(c.real("run.t_stop"), interval, "msd.sample_interval");
  add_time_averaged_msd<D>(run, std::make_shared<EveryTime>(interval, Trigger::never),
                           static_cast<std::uint64_t>(c.real("run.t_stop") / interval) + 1);
  run.stop_at_time(c.real("run.t_stop"));
}

void write(const EdmdMsdResult& r, H5mdFile& file) {
  write_ensemble_msd(file, r, 3, [](std::size_t k, double) { return static_cast<std::int64_t>(k); });
  file.write_attribute("/parameters/derived", "initial_temperature", r.temperature0);
  file.write_attribute("/parameters/derived", "enskog_diffusivity0", r.enskog.diffusivity0);
  file.write_attribute("/parameters/derived", "gamma0", r.enskog.gamma0);
  file.write_attribute("/parameters/derived", "haff_tau0", r.enskog.tau0);
  file.write_attribute("/observables", "long_time_slope", r.long_time_slope);
  file.write_attribute("/observables", "msd_exponent", r.msd_exponent);
  spdlog::info("MSD({}) = {:.5g} +- {:.2g} (theory {:.5g}); slope over the last decade {:.4f} = {:.4f} x 6 D0 (Enskog)",
               r.time.back(), r.msd.back(), r.msd_stderr.back(), r.msd_theory.back(), r.long_time_slope,
               r.long_time_slope / (6 * r.enskog.diffusivity0));
  spdlog::info("at late times MSD = c + a t^gamma with gamma = {:.4f}", r.msd_exponent);
}

void declare_keys(ConfigSchema& s) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  edmd::GasDefaults gas;
  gas.restitution = 1.0;
  edmd::declare_gas_keys(s, gas);
  declare_stored_start_keys(s);
  declare_ensemble_keys(s, 4);
  s.real("output.first", 0.001, 0.0, inf, "first output time after t = 0", true)
      .integer("output.points_per_decade", 10, 1, 1000, "log-spaced outputs per decade");
  declare_msd_keys(s, MsdDefaults{0, 0.05});
}

const Scenario brownian_edmd{
    .name = "brownian_edmd",
    .summary = "MSD, diffusivity and time-averaged MSD of the event-driven gas against Enskog theory",
    .default_output = "brownian_edmd.h5md",
    .keys = declare_keys,
    .build = build,
    .adopt = adopt_stored_state_as_one_run,
    .members = ensemble_members,
    .reduce = [](const EnsembleResults& results, H5mdFile& file) { write(reduce_edmd_msd(results), file); },
};

}  // namespace

EdmdMsdResult reduce_edmd_msd(const EnsembleResults& results) {
  const Config& config = results.config;
  const auto runs = static_cast<double>(results.members.size());
  double t0 = 0.0;
  for (const auto& m : results.members) t0 += m.derived.at("initial_temperature") / runs;
  const double count = static_cast<double>(config.integer("system.count"));
  auto enskog = sde::model_from_gas(count, config.real("system.radius"), config.real("collision.restitution"), t0,
                                   config.real("system.mass"), std::pow(config.real("system.box_length"), 3));
  std::vector<double> time, theory;
  for (const auto& sample : results.members.front().history.at("msd")) time.push_back(sample.time);
  const double viscoelastic = config.real("collision.viscoelastic_speed");
  if (viscoelastic > 0) {
    // Viscoelastic spheres: D(t) = D0 sqrt(T/T0) = D0 (1 + t/tau)^-5/6 with
    // tau of their Haff's law, so MSD = 36 D0 tau ((1 + t/tau)^1/6 - 1), the
    // long-time (t >> 1/gamma0) form: t^1/6 at t >> tau.
    const double volume = std::pow(config.real("system.box_length"), 3);
    const double radius = config.real("system.radius"), mass = config.real("system.mass");
    const double eta = theory::packing_fraction<3>(count, radius, volume);
    enskog.tau0 = theory::viscoelastic_haff_time<3>(
        viscoelastic, t0, mass, theory::collision_frequency<3>(count / volume, 2 * radius, t0, mass, eta));
    for (double t : time) theory.push_back(36.0 * enskog.diffusivity0 * enskog.tau0 * (std::pow(1.0 + t / enskog.tau0, 1.0 / 6.0) - 1.0));
  } else {
    for (double per_axis : sde::moment_msd(enskog, t0 / config.real("system.mass"), time)) theory.push_back(3.0 * per_axis);
  }
  EdmdMsdResult out{reduce_ensemble_msd(results, std::move(time), std::move(theory), config.real("msd.sample_interval"))};
  out.temperature0 = t0;
  out.enskog = enskog;
  // The MSD's growth exponent, MSD = c + a t^gamma fitted over the
  // asymptotic window (t >= 100 Haff times), or the last decade where that
  // window is shorter (an elastic gas: gamma -> 1).
  const double window = std::min(100.0 * enskog.tau0, 0.1 * config.real("run.t_stop"));
  std::vector<double> late_time, late_msd;
  for (std::size_t k = 0; k < out.time.size(); ++k)
    if (out.time[k] >= window) {
      late_time.push_back(out.time[k]);
      late_msd.push_back(out.msd[k]);
    }
  out.msd_exponent = fit_offset_power_law(late_time, late_msd, 0.01, 2.0).exponent;
  // Slope over the last decade (least squares).
  LineFit last_decade;
  for (std::size_t k = 0; k < out.time.size(); ++k)
    if (out.time[k] >= 0.1 * config.real("run.t_stop")) last_decade.add(out.time[k], out.msd[k]);
  out.long_time_slope = last_decade.slope();
  return out;
}

EdmdMsdResult measure_edmd_msd(const Config& config) { return reduce_edmd_msd(simulate_ensemble(brownian_edmd, config)); }

GRANFLOW_REGISTER_SCENARIO(brownian_edmd, brownian_edmd)

}  // namespace granflow::scenarios
