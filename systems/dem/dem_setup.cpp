#include "systems/dem/dem_setup.hpp"

#include "systems/dem/dem_domain_step.hpp"
#include "systems/dem/position_verlet.hpp"
#include "systems/dem/velocity_verlet.hpp"
#include "systems/dem/wall_observer.hpp"

namespace granflow::dem {

void declare_dem_keys(ConfigSchema& s, const DemDefaults& d) {
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


namespace {

// The step over MPI ranks (dem_domain_step.hpp) in place of the chain, for
// what it offers: velocity Verlet on spheres kept in cell order, in a box
// closed along z (the slabs' axis); the rest is refused, naming what to
// change. Call once the whole system's lists are built.
void add_domain_step(Run& run, const std::array<bool, 3>& periodic, double dt) {
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
  const double largest =
      -run.communicator()->least_across({radii.empty() ? 0.0 : -*std::max_element(radii.begin(), radii.end())}).front();
  const std::size_t spheres = world.has_resource<BedByPart>()     ? world.resource<BedByPart>().spheres
                              : world.has_resource<ResumedPart>() ? world.resource<ResumedPart>().spheres
                                                                  : world.size();
  const auto& box = world.resource<Box<3>>();
  const CellGrid<3> layers =
      domain_layers(box.length, box.periodic, largest, world.resource<NeighbourList<3>>().skin, spheres);
  run.step<DemDomainStep>(*run.communicator(), dt, layers,
                          DemDomainBalance{c.integer("balance.every_steps"), c.real("balance.threshold")});
  run.mark_distributed();
  run.derive("ranks", static_cast<double>(ranks));
  run.derive("slab_layers", static_cast<double>(layers.cells(2)));
}

}  // namespace

double add_dem_step(Run& run, const std::array<double, 3>& box, const std::array<bool, 3>& periodic,
                           const ContactLaw& law, std::vector<DemWall> walls, const std::string& damping_key,
                           const TriggerPtr& outputs) {
  constexpr int D = 3;
  const Config& c = run.config();
  auto& world = run.world();
  const auto& g = c.reals("gravity.acceleration");
  if (g.size() != 3) throw ConfigError(fmt::format("gravity.acceleration has {} entries; it needs 3", g.size()));
  // Over ranks a fresh bed is made by parts (bed_by_part.hpp): what the
  // set-up needs of every sphere comes from every rank's.
  const Communicator* ranks = run.communicator();
  const bool by_part = world.has_resource<BedByPart>();
  auto& watch = world.emplace_resource<DemWatch<D>>(wall_reach(box, periodic, walls));
  {
    const auto& x = world.component<Position<D>>();
    const bool ids = world.has_component<ParticleId>();
    for (std::size_t i = 0; i < world.size(); ++i)
      for (std::size_t a = 0; a < 3; ++a)
        if (!(x[i][a] >= watch.lower[a] && x[i][a] <= watch.upper[a]))
          throw ConfigError(fmt::format(
              "the walls leave sphere {} of the initial state outside them ({} = {:.6g}, the walls reach [{:.6g}, "
              "{:.6g}]); check walls and system.box",
              ids ? world.component<ParticleId>()[i] : i, "xyz"[a], x[i][a], watch.lower[a], watch.upper[a]));
  }
  const auto& masses = world.component<Mass>().values;
  double lightest = masses.empty() ? std::numeric_limits<double>::infinity()
                                   : *std::min_element(masses.begin(), masses.end());
  if (ranks && ranks->size() > 1) lightest = ranks->least_across({lightest}).front();
  if (!std::isfinite(lightest)) lightest = 1.0;
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
      choose_time_step(c, cases, contact_demand(world, walls, {g[0], g[1], g[2]}, ranks), walls, friction);
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
  run.keep(kept_lists, neighbours);
  if (world.has_resource<ResumedPart>()) read_lists_of_part(run, world.resource<ResumedPart>(), neighbours);
  if (!run.resuming() && !by_part) {
    // A resumed run has its lists, forces and torques from the checkpoint
    // (evaluating them again would stretch the friction springs twice); a
    // bed made by parts has them from the step's start over the ranks.
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
  // The build count is kept in the World's lists on every rank (over ranks
  // the step's own lists count them), so the end gathers nothing for it.
  run.at_finish([&run](H5mdFile& file, const RunOutcome&) {
    const auto& nl = run.world().resource<NeighbourList<D>>();
    file.write_attribute("/observables", "neighbour_list_builds", static_cast<double>(nl.builds));
    spdlog::info("{} steps, {} neighbour-list builds", run.clock().step, nl.builds);
  });
  return dt;
}

}  // namespace granflow::dem
