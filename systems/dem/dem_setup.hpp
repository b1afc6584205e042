#pragma once
// What the soft-sphere scenarios share: their keys (declare_dem_keys), the
// contact law and time step from them, the walls of the `walls` list, and
// the step chain with its energy observer (add_dem_step): velocity Verlet
// around the neighbour lists and contact forces, the energy ledger.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "components/angular_velocity.hpp"
#include "components/force.hpp"
#include "components/image_count.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/core/communicator.hpp"
#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "engine/core/units.hpp"
#include "engine/run/run.hpp"
#include "systems/dem/bed_by_part.hpp"
#include "systems/dem/contact_forces.hpp"
#include "systems/dem/dem_energy.hpp"
#include "systems/dem/dem_watchdog.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/resumed_part.hpp"
#include "systems/dem/time_step.hpp"
#include "systems/geometry/slab_domain.hpp"
#include "systems/initial/stored_start.hpp"
#include "systems/observables/particle_frames.hpp"

namespace granflow::dem {

struct DemDefaults {
  std::int64_t count = 300;
  std::vector<double> box{20.0, 4.0, 40.0};
  double stiffness = 2e4;
  double restitution = 0.7;
  double amplitude = 0.5;
  double frequency = 2.5;
  double t_stop = 300.0;
  double output_interval = 1.0;
  std::string motion = "sine";
};

void declare_dem_keys(ConfigSchema& s, const DemDefaults& d);

inline ContactLaw law_from(const Config& c, double stiffness, double restitution) {
  ContactLaw law;
  law.model = c.text("contact.model") == "hertz" ? ContactModel::hertz : ContactModel::lsd;
  law.stiffness = stiffness;
  law.damping = law.model == ContactModel::lsd ? ContactLaw::lsd_damping_factor(restitution) : c.real("contact.hertz_damping");
  return law;
}

inline std::array<double, 3> box_from(const Config& c, const char* scenario) {
  const auto& edges = c.reals("system.box");
  if (edges.size() != 3)
    throw ConfigError(fmt::format("system.box has {} entries; {} is 3D and needs 3", edges.size(), scenario));
  return {edges[0], edges[1], edges[2]};
}

inline WallMotion wall_motion(const std::string& name) { return name == "wiggle" ? WallMotion::wiggle : WallMotion::sine; }

// Whether contact.damping_rate (where the scenario has it) sets the damping
// of the spring-dashpot law instead of contact.restitution.
inline bool damped_at_rate(const Config& c) {
  return c.values().count("contact.damping_rate") && c.real("contact.damping_rate") > 0.0 &&
         c.text("contact.model") != "hertz";
}

// The key that sets the pairs' damping under contact.model.
inline std::string damping_key(const Config& c) {
  if (damped_at_rate(c)) return "contact.damping_rate";
  return c.text("contact.model") == "hertz" ? "contact.hertz_damping" : "contact.restitution";
}

// The largest number of height-profile layers (of one sphere diameter) a box may have.
inline constexpr double most_profile_layers = 1e6;

// A box that holds spheres of `radius` with room to move, and whose
// height profiles fit in memory; refused with the keys named otherwise.
inline void require_room(const std::array<double, 3>& box, double radius) {
  for (std::size_t a = 0; a < 3; ++a)
    if (!(box[a] > 4.0 * radius))
      throw ConfigError(fmt::format("system.box = [{}, {}, {}] is too small for spheres of particle.radius = {}: every "
                                    "edge must exceed two diameters ({})",
                                    box[0], box[1], box[2], radius, 4.0 * radius));
  if (box[2] / (2.0 * radius) > most_profile_layers)
    throw ConfigError(fmt::format("system.box z = {} holds {:.3g} layers of spheres of particle.radius = {} for the "
                                  "height profiles; at most {:.0e}",
                                  box[2], box[2] / (2.0 * radius), radius, most_profile_layers));
}

// The walls of the `walls` list (empty where none is given).
inline std::vector<DemWall> walls_from(const Config& c, const std::array<double, 3>& box) {
  std::vector<DemWall> walls;
  const auto tables = c.tables("walls");
  for (std::size_t k = 0; k < tables.size(); ++k) {
    const Config& t = tables[k];
    DemWall w;
    w.axis = t.text("axis") == "x" ? 0 : t.text("axis") == "y" ? 1 : 2;
    w.rest = t.real("position");
    if (w.rest < 0.0 || w.rest > box[static_cast<std::size_t>(w.axis)])
      throw ConfigError(fmt::format("walls[{}].position = {} is outside the box (0 to {} along {})", k, w.rest,
                                    box[static_cast<std::size_t>(w.axis)], t.text("axis")));
    w.side = w.rest < 0.5 * box[static_cast<std::size_t>(w.axis)] ? -1 : +1;
    w.amplitude = t.real("amplitude");
    w.omega = 2.0 * std::numbers::pi * t.real("frequency");
    w.motion = wall_motion(t.text("motion"));
    w.law = law_from(c, t.real("stiffness") > 0 ? t.real("stiffness") : c.real("contact.stiffness"),
                     t.real("restitution") > 0 ? t.real("restitution") : c.real("contact.restitution"));
    walls.push_back(w);
  }
  return walls;
}

// The pair law of contact.model with contact.damping_rate, LAMMPS's
// gamma_n (a damping force m_eff gamma_n times the normal speed), for
// contacts of reduced mass `m_eff`, where the scenario has that key and it
// is positive; else the law of contact.restitution (law_from).
inline ContactLaw law_for_mass(const Config& c, double m_eff) {
  ContactLaw law = law_from(c, c.real("contact.stiffness"), c.real("contact.restitution"));
  if (damped_at_rate(c)) law.damping = m_eff * c.real("contact.damping_rate") / std::sqrt(m_eff * law.stiffness);
  return law;
}

// The walls of the `walls` list, or where it gives none a wall on both
// sides of every axis not in `periodic`, the floor (lower z) moving as
// shaking.* say, every one with contact law `law`.
inline std::vector<DemWall> walls_or_box_sides(const Config& c, const std::array<double, 3>& box,
                                               const std::array<bool, 3>& periodic, const ContactLaw& law) {
  std::vector<DemWall> walls = walls_from(c, box);
  if (!walls.empty()) return walls;
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, +1}) {
      if (periodic[static_cast<std::size_t>(axis)]) continue;
      DemWall w;
      w.axis = axis;
      w.side = side;
      w.rest = side < 0 ? 0.0 : box[static_cast<std::size_t>(axis)];
      w.law = law;
      if (axis == 2 && side < 0) {
        w.amplitude = c.real("shaking.amplitude");
        w.omega = 2.0 * std::numbers::pi * c.real("shaking.frequency");
        w.motion = wall_motion(c.text("shaking.motion"));
      }
      walls.push_back(w);
    }
  return walls;
}

// A stored state (initial.from) of soft spheres: contacts may overlap by a
// little (beyond half a radius, no contact law of a settled bed does), and
// spheres rest against walls inside the box rather than a radius from its
// edges (the walls' own check, add_dem_step, then holds them to the walls).
inline constexpr StoredStateLimits stored_state_limits{0.5, false};

// The columns of `n` spheres of one radius and mass (positions and
// velocities left for the caller), for a scenario's initial state.
struct SphereColumns {
  Position<3>& x;
  Velocity<3>& v;
};
inline SphereColumns add_spheres(World& world, std::size_t n, double radius, double mass) {
  world.resize(n);
  auto& x = world.add_component<Position<3>>();
  auto& v = world.add_component<Velocity<3>>();
  world.add_component<Force<3>>();
  world.add_component<Radius>().values.assign(n, radius);
  world.add_component<Mass>().values.assign(n, mass);
  // Storage order changes at the neighbour-list builds; output follows the ids.
  auto& id = world.add_component<ParticleId>().values;
  id.resize(n);
  std::iota(id.begin(), id.end(), 0u);
  return {x, v};
}

// The spheres `made` of a bed of `total` (bed_by_part.hpp), each with its
// index as its id; over `ranks` the World says that it holds a part.
inline SphereColumns add_spheres(World& world, const std::vector<std::size_t>& made, std::size_t total,
                                 const Communicator* ranks, double radius, double mass) {
  SphereColumns columns = add_spheres(world, made.size(), radius, mass);
  auto& id = world.component<ParticleId>().values;
  for (std::size_t k = 0; k < made.size(); ++k) id[k] = static_cast<std::uint32_t>(made[k]);
  if (ranks && ranks->size() > 1) world.emplace_resource<BedByPart>().spheres = total;
  return columns;
}

// How far the walls reach along each axis (the watchdog's bounds): every
// closed axis needs a wall on each side, or a sphere could leave the box.
inline DemWatch<3> wall_reach(const std::array<double, 3>& box, const std::array<bool, 3>& periodic,
                              const std::vector<DemWall>& walls) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  DemWatch<3> watch;
  for (std::size_t a = 0; a < 3; ++a) {
    watch.lower[a] = periodic[a] ? -inf : inf;
    watch.upper[a] = periodic[a] ? inf : -inf;
  }
  for (const DemWall& w : walls) {
    if (w.divider) continue;
    const auto a = static_cast<std::size_t>(w.axis);
    if (w.side < 0) watch.lower[a] = std::min(watch.lower[a], w.centre() - std::abs(w.amplitude));
    else watch.upper[a] = std::max(watch.upper[a], w.centre() + std::abs(w.amplitude));
  }
  constexpr const char* name[] = {"x", "y", "z"};
  for (std::size_t a = 0; a < 3; ++a)
    for (int side : {-1, +1})
      if (std::isinf(side < 0 ? watch.lower[a] : watch.upper[a]) && !periodic[a])
        throw ConfigError(fmt::format(
            "walls: the box is closed along {} but has no wall on its {} side ({} = {}), so spheres could leave it; "
            "add one, e.g. {{axis = \"{}\", position = {}}}",
            name[a], side < 0 ? "lower" : "upper", name[a], side < 0 ? 0.0 : box[a], name[a], side < 0 ? 0.0 : box[a]));
  return watch;
}

// What the run can do to its contacts, from its initial state, walls and
// gravity (stability_limits.hpp); over `ranks` (where each may hold a part
// of the bed), from every rank's spheres.
inline ContactDemand contact_demand(const World& world, const std::vector<DemWall>& walls, const std::array<double, 3>& g,
                                    const Communicator* ranks) {
  const auto& x = world.component<Position<3>>();
  const auto& v = world.component<Velocity<3>>();
  const auto& m = world.component<Mass>();
  const auto& r = world.component<Radius>();
  const double g_norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  constexpr double inf = std::numeric_limits<double>::infinity();
  // Each the least over the spheres: radius, minus the mass, minus the
  // speed, the height along gravity and minus it.
  std::vector<double> least{inf, inf, inf, inf, inf};
  for (std::size_t i = 0; i < world.size(); ++i) {
    least[0] = std::min(least[0], r[i]);
    least[1] = std::min(least[1], -m[i]);
    least[2] = std::min(least[2], -v[i].norm());
    if (g_norm > 0.0) {
      const double h = -(g[0] * x[i][0] + g[1] * x[i][1] + g[2] * x[i][2]) / g_norm;
      least[3] = std::min(least[3], h);
      least[4] = std::min(least[4], -h);
    }
  }
  if (ranks && ranks->size() > 1) least = ranks->least_across(least);
  const bool any = least[0] < inf;
  ContactDemand demand;
  demand.radius = any ? least[0] : 0.0;
  const double heaviest = any ? -least[1] : 0.0;
  const double fastest = any ? -least[2] : 0.0;
  double wall_speed = 0.0, reach = 0.0;
  for (const DemWall& w : walls) {
    wall_speed = std::max(wall_speed, std::abs(w.amplitude * w.omega));
    reach = std::max(reach, std::abs(w.amplitude));
  }
  const double height = g_norm > 0.0 && any ? -least[4] - least[3] + 2.0 * reach : 0.0;
  const double speeds[] = {2.0 * fastest, 2.0 * wall_speed, std::sqrt(2.0 * g_norm * height)};
  const char* origins[] = {"the initial velocities", "the walls' motion",
                           "a fall through the bed's height under gravity.acceleration"};
  const auto largest = static_cast<std::size_t>(std::max_element(std::begin(speeds), std::end(speeds)) - speeds);
  demand.speed = speeds[largest];
  demand.speed_origin = origins[largest];
  demand.load = demand.radius > 0.0 ? heaviest * g_norm * (height / (2.0 * demand.radius) + 1.0) : 0.0;
  return demand;
}

// The resources, the forces of the initial state, the time step (chosen
// and checked against every contact, time_step.hpp), the step chain with
// its watchdog (over MPI ranks where the run has a communicator,
// dem_domain_step.hpp), the energy and wall observers at `outputs`, the
// particle frames (output.positions), the stop at run.t_stop.
// `damping_key` names the key that sets the pairs' damping. Call after
// run.initial_state. Returns the time step. Compiled once, in
// dem_setup.cpp: the step it assembles is most of a scenario's code.
double add_dem_step(Run& run, const std::array<double, 3>& box, const std::array<bool, 3>& periodic,
                    const ContactLaw& law, std::vector<DemWall> walls, const std::string& damping_key,
                    const TriggerPtr& outputs);

}  // namespace granflow::dem
