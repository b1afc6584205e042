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
#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "engine/core/units.hpp"
#include "engine/run/run.hpp"
#include "systems/dem/contact_forces.hpp"
#include "systems/dem/dem_domain_step.hpp"
#include "systems/dem/dem_energy.hpp"
#include "systems/dem/dem_watchdog.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/position_verlet.hpp"
#include "systems/dem/time_step.hpp"
#include "systems/dem/velocity_verlet.hpp"
#include "systems/dem/wall_observer.hpp"
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

inline void declare_dem_keys(ConfigSchema& s, const DemDefaults& d) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  declare_frame_keys(s, "final");
  s.integer("system.count", d.count, 1, 1000000, "number of spheres")
      .real_array("system.box", d.box, 0.0, 1e9, 3, 3, "box edge lengths along x, y, z")
      .real("particle.radius", 0.5, 0.0, inf, "sphere radius", true)
      .real("particle.mass", 1.0, 0.0, inf, "sphere mass", true)
      .choice("contact.model", "lsd", {"lsd", "hertz"},
              "normal contact force: linear spring-dashpot or Hertz with Kuwabara-Kono damping")
      .real("contact.stiffness", d.stiffness, 0.0, inf, "spring constant k (Hertz: of k delta^{3/2})", true)
      .real("contact.restitution", d.restitution, 0.0, 1.0,
            "restitution e of the linear spring-dashpot (sets its damping; > 0: at e = 0 the dashpot is critically "
            "damped and the spheres never separate)", true)
      .real("contact.hertz_damping", 0.0, 0.0, inf, "Hertz: the Kuwabara-Kono damping time A")
      .real("contact.friction", 0.0, 0.0, inf, "Coulomb friction mu of the tangential spring (0: frictionless, no rotation)")
      .real("contact.tangential_stiffness", 2.0 / 7.0, 0.0, inf, "tangential spring k_t / k_n (with friction)")
      .real("contact.tangential_damping", 0.5, 0.0, inf, "tangential dashpot gamma_t / gamma_n (with friction)")
      .real("shaking.amplitude", d.amplitude, 0.0, inf, "amplitude A of the floor's motion (shaking.motion)")
      .real("shaking.frequency", d.frequency, 0.0, inf, "frequency f of the floor's motion")
      .choice("shaking.motion", d.motion, {"sine", "wiggle"},
              "the floor's motion: sine, A sin(2 pi f t) about its rest position; wiggle, A (1 - cos 2 pi f t) "
              "above it, from rest (LAMMPS's fix wall/gran ... wiggle)")
      .real_array("gravity.acceleration", {0.0, 0.0, -1.0}, -1e300, 1e300, 3, 3, "gravity, one entry per axis")
      .real("neighbour.skin", 0.4, 0.0, inf, "Verlet skin, in sphere radii", true)
      .boolean("neighbour.reorder", true, "put the spheres in cell order at each neighbour-list build")
      .real("run.t_stop", d.t_stop, 0.0, inf, "simulated time to run", true)
      .real("run.dt", 0.0, 0.0, inf,
            "time step (0: a fiftieth of the shortest collision; checked against every contact, docs/dem.md)")
      .choice("run.integrator", "velocity_verlet", {"velocity_verlet", "position_verlet"},
              "velocity Verlet, or position Verlet with the backward-difference velocity")
      .real("output.interval", d.output_interval, 0.0, inf, "time between outputs", true);
  declare_slab_balance_keys(s, 100, 1.05, "two per sphere of its slab and one per listed pair, at the next list build");
  ConfigSchema wall;
  wall.choice("axis", "z", {"x", "y", "z"}, "the axis the wall is perpendicular to")
      .real("position", 0.0, 0.0, inf, "its position along that axis (below the middle: spheres above it)")
      .real("stiffness", 0.0, 0.0, inf, "its contact stiffness (0: contact.stiffness)")
      .real("restitution", 0.0, 0.0, 1.0,
            "its restitution (0: contact.restitution; as for pairs, e = 0 itself is no spring-dashpot: the spheres "
            "would never leave the wall)")
      .real("amplitude", 0.0, 0.0, inf, "amplitude of its motion along its normal")
      .real("frequency", 0.0, 0.0, inf, "frequency of that motion")
      .choice("motion", "sine", {"sine", "wiggle"},
              "sine: position + A sin(2 pi f t); wiggle: position + A (1 - cos 2 pi f t), from rest (LAMMPS's wiggle)");
  wall.unit("position", unit::length).unit("stiffness", "M T-2").unit("amplitude", unit::length).unit("frequency", unit::rate)
      .unit("restitution", unit::none);
  s.table_array("walls", std::move(wall), 0, 16, "walls (default: the scenario's, the floor shaking)");
  // A finished run (output.final_checkpoint) extends with --resume --set run.t_stop=...
  s.allow_change_on_resume("run.t_stop");
  s.unit("system.box", unit::length).unit("particle.radius", unit::length).unit("particle.mass", unit::mass)
      .unit("contact.stiffness", "M T-2").unit("contact.restitution", unit::none).unit("contact.hertz_damping", unit::time)
      .unit("contact.friction", unit::none)
      .unit("contact.tangential_stiffness", unit::none).unit("contact.tangential_damping", unit::none).unit("shaking.amplitude", unit::length).unit("shaking.frequency", unit::rate)
      .unit("gravity.acceleration", unit::acceleration).unit("neighbour.skin", unit::none).unit("run.t_stop", unit::time)
      .unit("run.dt", unit::time).unit("output.interval", unit::time);
}

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

// What the run can do to its contacts, from its initial state, walls and gravity (stability_limits.hpp).
inline ContactDemand contact_demand(const World& world, const std::vector<DemWall>& walls, const std::array<double, 3>& g) {
  const auto& x = world.component<Position<3>>();
  const auto& v = world.component<Velocity<3>>();
  const auto& m = world.component<Mass>();
  const auto& r = world.component<Radius>();
  ContactDemand demand;
  demand.radius = r.values.empty() ? 0.0 : *std::min_element(r.values.begin(), r.values.end());
  const double heaviest = m.values.empty() ? 0.0 : *std::max_element(m.values.begin(), m.values.end());
  double fastest = 0.0, wall_speed = 0.0, reach = 0.0;
  for (const auto& vi : v.values) fastest = std::max(fastest, vi.norm());
  for (const DemWall& w : walls) {
    wall_speed = std::max(wall_speed, std::abs(w.amplitude * w.omega));
    reach = std::max(reach, std::abs(w.amplitude));
  }
  const double g_norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  double height = 0.0;
  if (g_norm > 0.0 && !x.values.empty()) {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const auto& p : x.values) {
      const double h = -(g[0] * p[0] + g[1] * p[1] + g[2] * p[2]) / g_norm;
      low = std::min(low, h);
      high = std::max(high, h);
    }
    height = high - low + 2.0 * reach;
  }
  const double speeds[] = {2.0 * fastest, 2.0 * wall_speed, std::sqrt(2.0 * g_norm * height)};
  const char* origins[] = {"the initial velocities", "the walls' motion",
                           "a fall through the bed's height under gravity.acceleration"};
  const auto largest = static_cast<std::size_t>(std::max_element(std::begin(speeds), std::end(speeds)) - speeds);
  demand.speed = speeds[largest];
  demand.speed_origin = origins[largest];
  demand.load = demand.radius > 0.0 ? heaviest * g_norm * (height / (2.0 * demand.radius) + 1.0) : 0.0;
  return demand;
}

// The step over MPI ranks (dem_domain_step.hpp) in place of the chain, for
// what it offers: velocity Verlet on spheres kept in cell order, in a box
// closed along z (the slabs' axis); the rest is refused, naming what to
// change. Call once the whole system's lists are built.
inline void add_domain_step(Run& run, const std::array<bool, 3>& periodic, double dt) {
  const Config& c = run.config();
  const int ranks = run.communicator()->size();
  const auto refuse = [&](const std::string& what) {
    throw ConfigError(fmt::format("{} is not offered over several ranks (this run has {}); run this one without mpirun",
                                  what, ranks));
  };
  if (c.text("run.integrator") != "velocity_verlet")
    refuse(fmt::format("run.integrator = \"{}\" (velocity_verlet is)", c.text("run.integrator")));
  if (!c.boolean("neighbour.reorder"))
    refuse("neighbour.reorder = false (the ranks keep their spheres in cell order to sum as one rank does)");
  if (periodic[2]) refuse("a box periodic along z (the slabs lie along z)");
  World& world = run.world();
  const auto& radii = world.component<Radius>().values;
  const double largest = radii.empty() ? 0.0 : *std::max_element(radii.begin(), radii.end());
  const CellGrid<3> layers =
      list_cells(world.resource<Box<3>>(), 2.0 * largest + world.resource<NeighbourList<3>>().skin, world.size());
  run.step<DemDomainStep>(*run.communicator(), dt, layers,
                          DemDomainBalance{c.integer("balance.every_steps"), c.real("balance.threshold")});
  run.mark_distributed();
  run.derive("ranks", static_cast<double>(ranks));
  run.derive("slab_layers", static_cast<double>(layers.cells(2)));
}

// The resources, the forces of the initial state, the time step (chosen
// and checked against every contact, time_step.hpp), the step chain with
// its watchdog, the energy and wall observers at `outputs`, the particle
// frames (output.positions), the stop at run.t_stop. `damping_key` names
// the key that sets the pairs' damping. Call after run.initial_state.
// Returns the time step.
inline double add_dem_step(Run& run, const std::array<double, 3>& box, const std::array<bool, 3>& periodic,
                           const ContactLaw& law, std::vector<DemWall> walls, const std::string& damping_key,
                           const TriggerPtr& outputs) {
  constexpr int D = 3;
  const Config& c = run.config();
  auto& world = run.world();
  const auto& g = c.reals("gravity.acceleration");
  if (g.size() != 3) throw ConfigError(fmt::format("gravity.acceleration has {} entries; it needs 3", g.size()));
  auto& watch = world.emplace_resource<DemWatch<D>>(wall_reach(box, periodic, walls));
  {
    const auto& x = world.component<Position<D>>();
    for (std::size_t i = 0; i < world.size(); ++i)
      for (std::size_t a = 0; a < 3; ++a)
        if (!(x[i][a] >= watch.lower[a] && x[i][a] <= watch.upper[a]))
          throw ConfigError(fmt::format(
              "the walls leave sphere {} of the initial state outside them ({} = {:.6g}, the walls reach [{:.6g}, "
              "{:.6g}]); check walls and system.box",
              i, "xyz"[a], x[i][a], watch.lower[a], watch.upper[a]));
  }
  const auto& masses = world.component<Mass>().values;
  const double lightest = masses.empty() ? 1.0 : *std::min_element(masses.begin(), masses.end());
  std::vector<ContactCase> cases{{"sphere-sphere", law, 0.5 * lightest, "contact.stiffness", damping_key}};
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const bool known = std::any_of(cases.begin() + 1, cases.end(), [&](const ContactCase& seen) {
      return seen.law.model == walls[k].law.model && seen.law.stiffness == walls[k].law.stiffness &&
             seen.law.damping == walls[k].law.damping;
    });
    if (!known)
      cases.push_back({c.tables("walls").empty() ? (walls[k].divider ? "divider" : "wall") : fmt::format("walls[{}]", k),
                       walls[k].law, lightest, wall_key(c, k, "stiffness", "contact.stiffness"),
                       wall_key(c, k, "restitution", damping_key.c_str())});
  }
  TangentialFriction friction;
  friction.mu = c.real("contact.friction");
  friction.stiffness_ratio = c.real("contact.tangential_stiffness");
  friction.damping_ratio = c.real("contact.tangential_damping");
  if (friction.active() && friction.stiffness_ratio <= 0.0)
    throw ConfigError("contact.tangential_stiffness = 0 with contact.friction > 0: the tangential spring needs a stiffness");
  const TimeStep time_step =
      choose_time_step(c, cases, contact_demand(world, walls, {g[0], g[1], g[2]}), walls, friction);
  const double dt = time_step.dt, t_c = time_step.collision_time;
  watch.advice = fmt::format("The time step {:.4g} is {:.2g} x {} ({:.4g}) as estimated before the run; contacts "
                             "harder than that estimate need a smaller run.dt (e.g. {:.3g}) or stiffer springs",
                             dt, dt / time_step.shortest_scale, time_step.shortest_what, time_step.shortest_scale,
                             time_step.shortest_scale / 50.0);
  // A periodic axis shorter than twice the interaction range would let a
  // sphere touch two images of another; the lists see only the nearest.
  const double skin = c.real("neighbour.skin") * c.real("particle.radius");
  const double range = 4.0 * c.real("particle.radius") + skin;
  for (int a = 0; a < D; ++a)
    if (periodic[static_cast<std::size_t>(a)] && box[static_cast<std::size_t>(a)] <= 2.0 * range)
      throw ConfigError(fmt::format("system.box[{}] = {} is too short for a periodic axis: it must exceed twice the "
                                    "interaction range, 2 (2 particle.radius + skin) = {}",
                                    a, box[static_cast<std::size_t>(a)], 2.0 * range));
  auto& dem_box = world.emplace_resource<Box<D>>();
  dem_box.length = box;
  dem_box.periodic = periodic;
  auto& interactions = world.emplace_resource<DemInteractions<D>>();
  interactions.law = law;
  interactions.walls = std::move(walls);
  interactions.friction = friction;
  interactions.friction.dt = dt;
  const bool rotating = interactions.friction.active();
  if (rotating && c.text("run.integrator") == "position_verlet")
    throw ConfigError("contact.friction > 0 needs run.integrator = \"velocity_verlet\" (position Verlet has no rotation)");
  if (rotating && !world.has_component<AngularVelocity>()) {
    // Eigen leaves new vectors unset: the spheres start without spin.
    for (auto& w : world.add_component<AngularVelocity>().values) w.setZero();
    for (auto& t : world.add_component<Torque>().values) t.setZero();
  }
  auto& neighbours = world.emplace_resource<NeighbourList<D>>();
  neighbours.skin = skin;
  neighbours.reorder = c.boolean("neighbour.reorder");
  neighbours.keeps_history = rotating;
  neighbours.walls = interactions.walls.size();
  for (int a = 0; a < D; ++a) interactions.gravity[static_cast<std::size_t>(a)] = g[static_cast<std::size_t>(a)];
  auto& ledger = world.emplace_resource<DemLedger>();
  run.keep("energy", ledger);
  // The lists as they were, so a resumed run rebuilds (and reorders) when the
  // uninterrupted one would, and the friction springs carry over.
  run.keep("neighbours", neighbours);
  if (!run.resuming()) {
    // A resumed run has its lists, forces and torques from the checkpoint
    // (evaluating them again would stretch the friction springs twice).
    DemNeighbourList<D>().run(world);
    DemContactForces<D>().run(world);
    ledger.last_wall_power = interactions.wall_power;
    ledger.last_dissipation_power = interactions.dissipation_power;
  }
  const double omega = 2.0 * std::numbers::pi * c.real("shaking.frequency");
  run.derive("dt", dt);
  run.derive("contact_time", t_c);
  run.derive("shaking_acceleration_ratio",
             c.real("shaking.amplitude") * omega * omega / std::max(std::abs(g[2]), 1e-300));
  // Along periodic axes the spheres count their images, so that frames
  // unwrap (position + image L) as H5MD readers expect; a resumed run has
  // them from the checkpoint.
  if (std::find(periodic.begin(), periodic.end(), true) != periodic.end() && !world.has_component<ImageCount<D>>())
    for (auto& image : world.add_component<ImageCount<D>>().values) image.setZero();
  std::vector<std::string> boundary;
  for (bool p : periodic) boundary.push_back(p ? "periodic" : "none");
  run.box(std::vector<double>(box.begin(), box.end()), boundary);
  if (run.communicator()) {
    add_domain_step(run, periodic, dt);
  } else if (c.text("run.integrator") == "position_verlet") {
    // A resumed run has its previous positions from the checkpoint.
    if (!world.has_component<PreviousPosition<D>>()) DemPositionVerlet<D>::start(world, dt);
    run.step<DemPositionVerlet<D>>(dt);
    run.step<DemNeighbourList<D>>();
    run.step<DemContactForces<D>>();
  } else {
    run.step<DemKickDrift<D>>(dt);
    run.step<DemNeighbourList<D>>();
    run.step<DemContactForces<D>>();
    run.step<DemKick<D>>(dt);
  }
  if (!run.communicator()) run.step<DemEnergyAccount<D>>(dt);
  run.observe<DemEnergyObserver<D>>(outputs);
  run.keep("energy_watch", run.observe<DemEnergyWatch<D>>(outputs));
  run.observe<DemWallObserver<D>>(outputs);
  add_particle_frames<D>(run, outputs);
  run.stop_at_time(c.real("run.t_stop"));
  run.finished_reason("reached run.t_stop");
  const auto n = static_cast<double>(c.integer("system.count"));
  run.rate("particle-steps/s", [&run, n] { return n * static_cast<double>(run.clock().step); });
  run.at_finish([&run](H5mdFile& file, const RunOutcome&) {
    const auto& nl = run.world().resource<NeighbourList<D>>();
    file.write_attribute("/observables", "neighbour_list_builds", static_cast<double>(nl.builds));
    spdlog::info("{} steps, {} neighbour-list builds", run.clock().step, nl.builds);
  });
  return dt;
}

}  // namespace granflow::dem
