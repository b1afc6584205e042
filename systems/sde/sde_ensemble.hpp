#pragma once
// The ensemble an SDE MSD study integrates: `system.count` independent
// particles started at the origin, stepped with run.dt up to run.t_stop and
// observed at log-spaced whole steps; their initial velocities are drawn
// from the noise's stationary Gaussian at t = 0 or at one speed in random
// directions (as the hard-sphere gas starts).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/config.hpp"
#include "engine/core/output_times.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/world.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/sde/sde_model.hpp"
#include "systems/sde/sde_parameters.hpp"
#include "systems/sde/sde_theory.hpp"

namespace granflow::sde {

// The keys the functions below read besides the model's and the step's:
// the start and the output times.
inline void declare_ensemble_keys(ConfigSchema& s) {
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
}

struct EnsembleStepping {
  double dt;
  std::int64_t total_steps;
  std::vector<std::int64_t> output_steps;  // log-spaced output times rounded to whole steps, t = 0 left out
  Scheme scheme;
  double initial_velocity_variance;  // per component
  // Euler-Maruyama past its stability limit: until when (0: it is not).
  double unstable_until = 0.0;
};

// The stepping of `config`, refusing (ConfigError) what the theory curve
// cannot do. Euler-Maruyama past its stability limit is allowed (its
// instability is a result worth showing); the run warns (warn_if_unstable)
// and its watchdog stops it once the MSD overflows.
inline EnsembleStepping ensemble_stepping_from(const Config& config, const SdeModel& model, int dimension) {
  EnsembleStepping s;
  s.dt = config.real("run.dt");
  const double t_stop = config.real("run.t_stop");
  s.total_steps = static_cast<std::int64_t>(std::llround(t_stop / s.dt));
  if (s.total_steps < 1 || s.total_steps > 1e12)
    throw ConfigError(fmt::format("run.t_stop / run.dt = {:.3g} steps: allowed is 1 to 1e12", t_stop / s.dt));
  s.output_steps = log_output_steps(t_stop, config.real("output.first"),
                                    static_cast<int>(config.integer("output.points_per_decade")), s.dt);
  s.output_steps.erase(s.output_steps.begin());  // the MSD is 0 at t = 0
  s.scheme = scheme_from(config);
  if (s.scheme == Scheme::euler_maruyama) s.unstable_until = euler_maruyama_unstable_until(model, s.dt);
  if (model.scaled() && moment_msd_steps(model, t_stop) > 1e10)
    throw ConfigError(fmt::format("the UDSBM theory curve would need {:.3g} integration steps (gamma0 * tau0 = {:.3g}); "
                                  "lower gamma0 or tau0 (sde.* or gas.*) or run.t_stop",
                                  moment_msd_steps(model, t_stop), model.gamma0 * model.tau0));
  const double speed = config.real("initial.speed");
  s.initial_velocity_variance = config.text("initial.velocity") == "stationary"
                                    ? model.stationary_velocity_variance(0.0)
                                    : speed * speed / dimension;
  return s;
}

// The warnings of a step too long for the model: one that does not resolve
// the velocity relaxation, and an Euler-Maruyama step past its stability limit.
inline void warn_about_step(const EnsembleStepping& s, const SdeModel& model) {
  if (model.gamma0 * s.dt > 0.5)
    spdlog::warn("gamma0 * dt = {:.3g}: the step does not resolve the velocity relaxation time 1/gamma0; the MSD "
                 "is only right at times of many steps",
                 model.gamma0 * s.dt);
  if (s.unstable_until <= 0.0) return;
  const std::string until = std::isinf(s.unstable_until)
                                ? std::string("at every step")
                                : fmt::format("until t = {:.4g}, where gamma(t) dt falls below 2", s.unstable_until);
  spdlog::warn("run.dt = {} with gamma0 = {:.4g}: gamma0 * dt = {:.3g} is past Euler-Maruyama's stability limit "
               "gamma dt < 2, so velocities grow by |1 - gamma dt| >= 1 a step {}; run.scheme = \"exact_ou\" "
               "has no such limit",
               s.dt, model.gamma0, model.gamma0 * s.dt, until);
}

// `count` particles at the origin with velocities drawn as `config` says
// (stream sde_initial of `seed`, one substream per particle).
template <int D>
void start_at_origin(World& world, const Config& config, std::size_t count, const EnsembleStepping& s,
                     std::uint64_t seed) {
  const bool stationary = config.text("initial.velocity") == "stationary";
  world.resize(count);
  world.add_component<Position<D>>().values.assign(count, Vec<D>::Zero());
  auto& velocity = world.add_component<Velocity<D>>();
  for (std::size_t i = 0; i < count; ++i) {
    Philox random(stream::sde_initial, seed, 0, i);
    if (stationary)
      for (int a = 0; a < D; ++a) velocity[i][a] = std::sqrt(s.initial_velocity_variance) * random.normal();
    else
      velocity[i] = config.real("initial.speed") * random_direction<D>(random);
  }
}

}  // namespace granflow::sde
