#pragma once
// The time step of a soft-sphere run, chosen and checked before it starts
// against every contact it can have (stability_limits.hpp): run.dt, or a
// fiftieth of the shortest collision. Values that cannot be resolved,
// overdamped contacts, springs too soft for the speeds and loads of the
// run, walls that shake faster than the step follows, and runs of absurd
// length are refused with the key to change; coarse steps are warned about.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "systems/dem/contact_law.hpp"
#include "systems/dem/dem_walls.hpp"
#include "systems/dem/stability_limits.hpp"
#include "systems/dem/tangential_friction.hpp"

namespace granflow::dem {

// One kind of contact of the run and the keys that set its law.
struct ContactCase {
  std::string what;           // "sphere-sphere", "walls[1]", ...
  ContactLaw law;
  double m_eff = 1.0;
  std::string stiffness_key;  // e.g. contact.stiffness
  std::string damping_key;    // e.g. contact.restitution or contact.damping_rate
};

// What the run can be expected to do to its contacts.
struct ContactDemand {
  double speed = 0.0;  // the largest relative speed
  double load = 0.0;   // the largest force at rest
  double radius = 0.0;
  std::string speed_origin;  // what sets the speed, for messages
};

// The largest number of steps a run may take: beyond it the clock,
// step * dt, stops resolving dt, and no run would end in a lifetime.
inline constexpr double most_steps = 1e12;

struct TimeStep {
  double dt = 0.0;
  double collision_time = 0.0;  // of the first contact case (the pairs)
  double shortest_scale = 0.0;  // the shortest time scale of any contact
  std::string shortest_what;    // which contact and which scale
};

// The key whose value a wall's law or motion comes from.
inline std::string wall_key(const Config& c, std::size_t wall, const char* field, const char* scenario_key) {
  return c.tables("walls").empty() ? std::string(scenario_key) : fmt::format("walls[{}].{}", wall, field);
}

inline TimeStep choose_time_step(const Config& c, const std::vector<ContactCase>& cases, const ContactDemand& demand,
                                 const std::vector<DemWall>& walls, const TangentialFriction& friction) {
  for (std::size_t w = 0; w < walls.size(); ++w)
    if (!std::isfinite(walls[w].amplitude * walls[w].omega))
      throw ConfigError(fmt::format("{} = {:.4g} and {} = {:.4g}: the wall's speed is not finite",
                                    wall_key(c, w, "amplitude", "shaking.amplitude"), walls[w].amplitude,
                                    wall_key(c, w, "frequency", "shaking.frequency"),
                                    walls[w].omega / (2.0 * std::numbers::pi)));
  TimeStep step;
  step.shortest_scale = std::numeric_limits<double>::infinity();
  double default_dt = std::numeric_limits<double>::infinity(), largest = std::numeric_limits<double>::infinity();
  std::string limiting;
  // The tangential spring of a frictional contact oscillates against the
  // spheres' rotation as well: effective mass (2/7) m_eff for solid spheres,
  // stiffness and damping the given fractions of the normal ones.
  const auto tangential = [&](const ContactScales& normal) {
    ContactScales t = normal;
    const double ratio_k = friction.stiffness_ratio, ratio_g = friction.damping_ratio;
    t.spring_time = normal.spring_time * std::sqrt((2.0 / 7.0) / ratio_k);
    t.damping_time = ratio_g > 0.0 ? normal.damping_time * (2.0 / 7.0) / ratio_g : std::numeric_limits<double>::infinity();
    t.duration = t.spring_time * (normal.duration / normal.spring_time);
    return t;
  };
  std::vector<ContactScales> scales;
  std::vector<std::string> names;
  std::string limiting_law;
  const auto consider = [&](const ContactScales& s, const std::string& what, const std::string& law) {
    scales.push_back(s);
    names.push_back(what);
    default_dt = std::min(default_dt, s.default_step());
    if (s.largest_step() < largest) {
      largest = s.largest_step();
      limiting = what;
      limiting_law = law;
    }
    if (s.spring_time < step.shortest_scale) {
      step.shortest_scale = s.spring_time;
      step.shortest_what = fmt::format("the {} spring time", what);
    }
    if (s.damping_time < step.shortest_scale) {
      step.shortest_scale = s.damping_time;
      step.shortest_what = fmt::format("the {} damping time", what);
    }
  };
  for (const ContactCase& k : cases) {
    const ContactScales s = contact_scales(k.law, k.m_eff, demand.speed, demand.load);
    if (!usable_time(s.shortest()) || !usable_time(s.default_step()))
      throw ConfigError(fmt::format(
          "particle.mass = {:.4g} and {} = {:.4g} give the {} contact no time scale a double can step through "
          "(spring {:.4g}, dashpot {:.4g}); choose values nearer 1 in reduced units",
          c.real("particle.mass"), k.stiffness_key, k.law.stiffness, k.what, s.spring_time, s.damping_time));
    if (s.overdamped)
      throw ConfigError(fmt::format(
          "{} = {}: the {} contact is overdamped (the dashpot's rate gamma / 2 m_eff = {:.4g} is at least the spring's "
          "angular frequency {:.4g}), so the spheres never separate; use a smaller value",
          k.damping_key, c.values().count(k.damping_key) ? to_string(c.values().at(k.damping_key)) : "its value", k.what,
          k.law.gamma(k.m_eff) / (2.0 * k.m_eff), std::sqrt(k.law.stiffness / k.m_eff)));
    if (!(s.overlap < demand.radius)) {
      const double want = 0.1 * demand.radius;
      const double stiffness =
          k.law.model == ContactModel::lsd
              ? std::max(k.m_eff * demand.speed * demand.speed / (want * want), demand.load / want)
              : std::max(1.25 * k.m_eff * demand.speed * demand.speed / std::pow(want, 2.5),
                         demand.load / std::pow(want, 1.5));
      throw ConfigError(fmt::format(
          "{} = {:.4g} is too soft for this run: {} contacts would overlap by {:.3g} sphere radii (relative speeds up "
          "to {:.4g} from {}; a resting column's weight {:.4g}), so spheres would pass through each other and the "
          "walls; raise it to about {:.3g}, or lower gravity.acceleration or the shaking",
          k.stiffness_key, k.law.stiffness, k.what, s.overlap / demand.radius, demand.speed, demand.speed_origin,
          demand.load, stiffness));
    }
    if (s.overlap > 0.5 * demand.radius)
      spdlog::warn("{} contacts may overlap by {:.2g} sphere radii ({} = {:.4g}): a stiffer contact keeps them apart",
                   k.what, s.overlap / demand.radius, k.stiffness_key, k.law.stiffness);
    const std::string law = fmt::format("{} = {:.4g}", k.stiffness_key, k.law.stiffness);
    consider(s, k.what, law);
    if (friction.active())
      consider(tangential(s), "tangential " + k.what,
               fmt::format("{}, contact.tangential_stiffness = {:.4g}", law, friction.stiffness_ratio));
  }
  step.collision_time = scales.empty() ? 0.0 : scales.front().duration;
  step.dt = c.real("run.dt") > 0.0 ? c.real("run.dt") : default_dt;
  if (c.real("run.dt") > 0.0 && step.dt > largest)
    throw ConfigError(fmt::format(
        "run.dt = {:.4g} cannot resolve the {} contact ({}): it is {:.3g} x the largest stable step {:.4g} ({} is "
        "{:.4g}); use run.dt <= {:.3g}, or 0 for the default {:.3g}",
        step.dt, limiting, limiting_law, step.dt / largest, largest, step.shortest_what, step.shortest_scale, largest, default_dt));
  for (std::size_t k = 0; k < scales.size(); ++k) {
    const ContactScales& s = scales[k];
    if (step.dt > s.spring_time / 10.0 || step.dt > s.damping_time / 5.0)
      spdlog::warn("run.dt = {:.3g} resolves the {} contact coarsely (spring time {:.3g}, damping time {:.3g}; "
                   "the default is {:.3g})", step.dt, names[k], s.spring_time, s.damping_time, default_dt);
  }
  for (std::size_t w = 0; w < walls.size(); ++w)
    if (walls[w].amplitude > 0.0 && walls[w].omega > 0.0 && 2.0 * std::numbers::pi / walls[w].omega < 20.0 * step.dt)
      throw ConfigError(fmt::format(
          "{} = {:.4g}: the wall's period {:.4g} is shorter than 20 time steps (dt = {:.4g}); at most {:.4g}",
          wall_key(c, w, "frequency", "shaking.frequency"), walls[w].omega / (2.0 * std::numbers::pi),
          2.0 * std::numbers::pi / walls[w].omega, step.dt, 1.0 / (20.0 * step.dt)));
  const double t_stop = c.real("run.t_stop");
  if (t_stop < step.dt)
    throw ConfigError(fmt::format("run.t_stop = {:.4g} is shorter than one time step (dt = {:.4g})", t_stop, step.dt));
  if (t_stop / step.dt > most_steps)
    throw ConfigError(fmt::format("run.t_stop = {:.4g} takes {:.3g} steps of dt = {:.4g}; at most {:.0e}", t_stop,
                                  t_stop / step.dt, step.dt, most_steps));
  if (c.real("output.interval") < step.dt)
    throw ConfigError(fmt::format("output.interval = {:.4g} is shorter than the time step (dt = {:.4g})",
                                  c.real("output.interval"), step.dt));
  return step;
}

}  // namespace granflow::dem
