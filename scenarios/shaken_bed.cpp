// Soft spheres shaken from below in a box split by a divider (the granular
// Maxwell demon: Schlichting & Nordmeier 1996, Eggers 1999, van der Meer et
// al. 2002): a floor moving as A sin(2 pi f t), gravity, linear
// spring-dashpot (or Hertz) contacts, walls on every side and a divider
// from the floor up to divider.height at divider.position along x. Strong
// shaking shares the spheres equally between the compartments; weak
// shaking lets them cluster in one. Observables: the asymmetry
// (N_L - N_R)/N, the flux over the divider each way, the energies and the
// balance of what the floor injects and the contacts dissipate, the
// contact count and coordination number.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/rng.hpp"
#include "engine/run.hpp"
#include "engine/scenario.hpp"
#include "engine/stream_ids.hpp"
#include "engine/units.hpp"
#include "systems/dem/compartments.hpp"
#include "systems/dem/contact_forces.hpp"
#include "systems/dem/dem_energy.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/velocity_verlet.hpp"

namespace granflow::scenarios {
namespace {

using dem::ContactLaw;
using dem::DemWall;

ContactLaw law_from(const Config& c, double stiffness, double restitution) {
  ContactLaw law;
  law.model = c.text("contact.model") == "hertz" ? dem::ContactModel::hertz : dem::ContactModel::lsd;
  law.stiffness = stiffness;
  law.damping = law.model == dem::ContactModel::lsd ? ContactLaw::lsd_damping_factor(restitution)
                                                    : c.real("contact.hertz_damping");
  return law;
}

void build(Run& run) {
  constexpr int D = 3;
  const Config& c = run.config();
  const auto& edges = c.reals("system.box");
  if (edges.size() != 3)
    throw ConfigError(fmt::format("system.box has {} entries; shaken_bed is 3D and needs 3", edges.size()));
  const std::array<double, D> box{edges[0], edges[1], edges[2]};
  const auto n = static_cast<std::size_t>(c.integer("system.count"));
  const double radius = c.real("particle.radius"), mass = c.real("particle.mass");
  if (c.real("contact.friction") > 0.0)
    throw ConfigError("contact.friction > 0: tangential friction is not built yet; use 0 (frictionless)");
  const ContactLaw law = law_from(c, c.real("contact.stiffness"), c.real("contact.restitution"));
  const double t_c = law.model == dem::ContactModel::lsd ? law.contact_time(0.5 * mass) : 0.0;
  double dt = c.real("run.dt");
  if (dt == 0.0) {
    if (law.model != dem::ContactModel::lsd)
      throw ConfigError("run.dt = 0 (t_c / 50) needs contact.model = \"lsd\"; give run.dt for Hertz contacts");
    dt = t_c / 50.0;
  }
  if (t_c > 0.0 && dt > t_c / 3.0)
    throw ConfigError(fmt::format("run.dt = {:.3g} cannot resolve a contact of duration t_c = {:.3g} (at most t_c / 3; "
                                  "t_c / 50 is the default)", dt, t_c));
  if (t_c > 0.0 && dt > t_c / 10.0)
    spdlog::warn("run.dt = {:.3g} is above t_c / 10 = {:.3g}: contacts are resolved coarsely", dt, t_c / 10.0);
  const double divider_x = c.real("divider.position") > 0 ? c.real("divider.position") : 0.5 * box[0];
  if (divider_x <= 2.0 * radius || divider_x >= box[0] - 2.0 * radius)
    throw ConfigError(fmt::format("divider.position = {} leaves a compartment narrower than a sphere (box x: {})",
                                  divider_x, box[0]));
  const double amplitude = c.real("shaking.amplitude"), frequency = c.real("shaking.frequency");
  const double omega = 2.0 * std::numbers::pi * frequency;

  // Walls: the given list, or the box's six sides with the floor shaking.
  std::vector<DemWall> walls;
  const auto tables = c.tables("walls");
  for (std::size_t k = 0; k < tables.size(); ++k) {
    const Config& t = tables[k];
    DemWall w;
    w.axis = t.text("axis") == "x" ? 0 : t.text("axis") == "y" ? 1 : 2;
    w.rest = t.real("position");
    if (w.rest < 0.0 || w.rest > box[w.axis])
      throw ConfigError(fmt::format("walls[{}].position = {} is outside the box (0 to {} along {})", k, w.rest,
                                    box[w.axis], t.text("axis")));
    w.side = w.rest < 0.5 * box[w.axis] ? -1 : +1;
    w.amplitude = t.real("amplitude");
    w.omega = 2.0 * std::numbers::pi * t.real("frequency");
    w.law = law_from(c, t.real("stiffness") > 0 ? t.real("stiffness") : c.real("contact.stiffness"),
                     t.real("restitution") > 0 ? t.real("restitution") : c.real("contact.restitution"));
    walls.push_back(w);
  }
  if (walls.empty())
    for (int axis = 0; axis < D; ++axis)
      for (int side : {-1, +1}) {
        DemWall w;
        w.axis = axis;
        w.side = side;
        w.rest = side < 0 ? 0.0 : box[axis];
        w.law = law;
        if (axis == 2 && side < 0) {
          w.amplitude = amplitude;
          w.omega = omega;
        }
        walls.push_back(w);
      }
  DemWall divider;
  divider.divider = true;
  divider.axis = 0;
  divider.height_axis = 2;
  divider.rest = divider_x;
  divider.top = c.real("divider.height");
  divider.law = law;
  if (divider.top > 0.0) walls.push_back(divider);

  // Spheres on a lattice from the floor up, alternately left and right.
  const double spacing = 2.2 * radius;
  const auto per_row = [&](double width) { return std::max(0, static_cast<int>(std::floor((width - 2 * radius) / spacing)) + 1); };
  const int across_y = per_row(box[1]);
  const std::array<int, 2> across_x{per_row(divider_x - 0.2 * radius), per_row(box[0] - divider_x - 0.2 * radius)};
  const double floor_clearance = amplitude + 1.1 * radius;
  const auto layers_needed = [&](int side) {
    const double per_layer = static_cast<double>(across_x[static_cast<std::size_t>(side)] * across_y);
    return per_layer > 0 ? std::ceil((static_cast<double>(n) / 2 + 1) / per_layer) : 1e300;
  };
  const double top = floor_clearance + spacing * std::max(layers_needed(0), layers_needed(1));
  if (top > box[2] - radius)
    throw ConfigError(fmt::format("system.count = {} spheres of radius {} do not fit below the top of the box "
                                  "(system.box z = {})", n, radius, box[2]));
  run.initial_state([&](World& world) {
    world.resize(n);
    auto& x = world.add_component<Position<D>>();
    auto& v = world.add_component<Velocity<D>>();
    world.add_component<Force<D>>();
    auto& r = world.add_component<Radius>();
    auto& m = world.add_component<Mass>();
    std::array<std::size_t, 2> placed{};
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t side = i % 2;
      const std::size_t k = placed[side]++;
      const auto row = static_cast<std::size_t>(across_x[side]), cols = static_cast<std::size_t>(across_y);
      const double x0 = side == 0 ? radius + 0.1 * radius : divider_x + radius + 0.1 * radius;
      x[i] = Vec<D>(x0 + spacing * static_cast<double>(k % row), radius + spacing * static_cast<double>((k / row) % cols),
                    floor_clearance + spacing * static_cast<double>(k / (row * cols)));
      Philox random(stream::dem_initial, run.seed(), 0, i);
      for (int a = 0; a < D; ++a) v[i][a] = 0.1 * random.normal();
      r[i] = radius;
      m[i] = mass;
    }
  });
  auto& world = run.world();
  auto& dem_box = world.emplace_resource<dem::DemBox<D>>();
  dem_box.length = box;
  dem_box.periodic = {false, false, false};
  world.emplace_resource<dem::NeighbourList<D>>().skin = c.real("neighbour.skin") * radius;
  auto& interactions = world.emplace_resource<dem::DemInteractions<D>>();
  interactions.law = law;
  interactions.walls = walls;
  const auto& g = c.reals("gravity.acceleration");
  if (g.size() != 3)
    throw ConfigError(fmt::format("gravity.acceleration has {} entries; shaken_bed needs 3", g.size()));
  for (int a = 0; a < D; ++a) interactions.gravity[a] = g[a];
  auto& ledger = world.emplace_resource<dem::DemLedger>();
  run.keep("energy", ledger);
  dem::DemNeighbourList<D>().run(world);
  dem::DemContactForces<D>().run(world);
  ledger.last_wall_power = interactions.wall_power;
  ledger.last_dissipation_power = interactions.dissipation_power;

  run.derive("dt", dt);
  run.derive("contact_time", t_c);
  run.derive("shaking_acceleration_ratio", amplitude * omega * omega / std::max(std::abs(g[2]), 1e-300));
  run.box(std::vector<double>(box.begin(), box.end()), std::vector<std::string>(D, "reflecting"));
  run.step<dem::DemKickDrift<D>>(dt);
  run.step<dem::DemNeighbourList<D>>();
  run.step<dem::DemContactForces<D>>();
  run.step<dem::DemKick<D>>(dt);
  run.step<dem::DemEnergyAccount<D>>(dt);
  const auto counts = std::make_shared<dem::CompartmentCounts>();
  counts->average_from = c.real("output.average_after");
  if (counts->average_from >= c.real("run.t_stop"))
    throw ConfigError(fmt::format("output.average_after = {} leaves nothing to average before run.t_stop = {}",
                                  counts->average_from, c.real("run.t_stop")));
  run.keep("compartments", *counts);
  run.observe<dem::CompartmentSampler<D>>(std::make_shared<EverySteps>(1), 0, divider_x, counts);
  const double t_stop = c.real("run.t_stop");
  const auto outputs = std::make_shared<EveryTime>(c.real("output.interval"), t_stop);
  run.observe<dem::CompartmentObserver<D>>(outputs, 0, divider_x, counts);
  run.observe<dem::DemEnergyObserver<D>>(outputs);
  run.stop_at_time(t_stop);
  run.finished_reason("reached run.t_stop");
  run.rate("particle-steps/s", [&run, n] { return static_cast<double>(n) * static_cast<double>(run.clock().step); });
  run.at_finish([counts](H5mdFile& file, const RunOutcome&) {
    const double samples = std::max(counts->samples, 1.0);
    file.write_attribute("/observables", "asymmetry_time_mean", counts->sum / samples);
    file.write_attribute("/observables", "asymmetry_abs_mean", counts->abs_sum / samples);
    file.write_attribute("/observables", "crossings", counts->crossings);
    const auto eggers = dem::fit_eggers_flux(counts->flux_samples);
    file.write_attribute("/observables", "eggers_flux_A", eggers[0]);
    file.write_attribute("/observables", "eggers_flux_B", eggers[1]);
    spdlog::info("time average after the warm-up ({:.0f} outputs): a = {:.3f}, |a| = {:.3f}; {:.0f} crossings; Eggers "
                 "flux fit A = {:.3g}, B = {:.3g} (equal sharing is stable for B < 4)",
                 counts->samples, counts->sum / samples, counts->abs_sum / samples, counts->crossings, eggers[0],
                 eggers[1]);
  });
  run.at_finish([&run](H5mdFile& file, const RunOutcome&) {
    const auto& nl = run.world().resource<dem::NeighbourList<D>>();
    file.write_attribute("/observables", "neighbour_list_builds", static_cast<double>(nl.builds));
    spdlog::info("{} steps, {} neighbour-list builds", run.clock().step, nl.builds);
  });
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(shaken_bed, Scenario{
  .name = "shaken_bed",
  .summary = "soft spheres shaken in a box split by a divider: the granular Maxwell demon (asymmetry against time)",
  .default_output = "shaken_bed.h5md",
  .keys = [](ConfigSchema& s) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    s.integer("system.count", 300, 1, 100000, "number of spheres")
        .real_array("system.box", {20.0, 4.0, 40.0}, 0.0, 1e9, 3, 3, "box edge lengths along x, y, z (walls on every side)")
        .real("particle.radius", 0.5, 0.0, inf, "sphere radius", true)
        .real("particle.mass", 1.0, 0.0, inf, "sphere mass", true)
        .choice("contact.model", "lsd", {"lsd", "hertz"}, "normal contact force: linear spring-dashpot or Hertz with "
                "Kuwabara-Kono damping")
        .real("contact.stiffness", 2e4, 0.0, inf, "spring constant k (Hertz: of k delta^{3/2})", true)
        .real("contact.restitution", 0.7, 0.0, 1.0, "restitution e of the linear spring-dashpot (sets its damping)")
        .real("contact.hertz_damping", 0.0, 0.0, inf, "Hertz: the Kuwabara-Kono damping time A")
        .real("contact.friction", 0.0, 0.0, inf, "Coulomb friction mu (0: frictionless; only 0 is built)")
        .real("shaking.amplitude", 0.5, 0.0, inf, "amplitude A of the floor's motion A sin(2 pi f t)")
        .real("shaking.frequency", 2.5, 0.0, inf, "frequency f of the floor's motion")
        .real("divider.position", 0.0, 0.0, inf, "x of the divider (0: the middle of the box)")
        .real("divider.height", 8.0, 0.0, inf, "the divider reaches from the floor to this height (0: no divider)")
        .real_array("gravity.acceleration", {0.0, 0.0, -1.0}, -1e300, 1e300, 3, 3, "gravity, one entry per axis")
        .real("neighbour.skin", 0.4, 0.0, inf, "Verlet skin, in sphere radii", true)
        .real("run.t_stop", 300.0, 0.0, inf, "simulated time to run", true)
        .real("run.dt", 0.0, 0.0, inf, "time step (0: t_c / 50 of a sphere pair)")
        .real("output.interval", 1.0, 0.0, inf, "time between outputs", true)
        .real("output.average_after", 100.0, 0.0, inf, "time after which a and |a| are averaged (the attributes "
              "asymmetry_time_mean, asymmetry_abs_mean)");
    ConfigSchema wall;
    wall.choice("axis", "z", {"x", "y", "z"}, "the axis the wall is perpendicular to")
        .real("position", 0.0, 0.0, inf, "its position along that axis (below the middle: spheres above it)")
        .real("stiffness", 0.0, 0.0, inf, "its contact stiffness (0: contact.stiffness)")
        .real("restitution", 0.0, 0.0, 1.0, "its restitution (0: contact.restitution)")
        .real("amplitude", 0.0, 0.0, inf, "amplitude of its motion along its normal")
        .real("frequency", 0.0, 0.0, inf, "frequency of that motion");
    wall.unit("position", unit::length).unit("stiffness", "M T-2").unit("amplitude", unit::length).unit("frequency", unit::rate)
        .unit("restitution", unit::none);
    s.table_array("walls", std::move(wall), 0, 16, "walls (default: the box's six sides, the floor shaking)");
    s.unit("system.box", unit::length).unit("particle.radius", unit::length).unit("particle.mass", unit::mass)
        .unit("contact.stiffness", "M T-2").unit("contact.restitution", unit::none).unit("contact.hertz_damping", unit::time)
        .unit("contact.friction", unit::none).unit("shaking.amplitude", unit::length).unit("shaking.frequency", unit::rate)
        .unit("divider.position", unit::length).unit("divider.height", unit::length)
        .unit("gravity.acceleration", unit::acceleration).unit("neighbour.skin", unit::none).unit("run.t_stop", unit::time)
        .unit("run.dt", unit::time).unit("output.interval", unit::time)
        .unit("output.average_after", unit::time);
  },
  .build = build,
})

}  // namespace granflow::scenarios
