#include "scenarios/scattering.hpp"

#include <fmt/format.h>

#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/run/run.hpp"
#include "engine/run/runner.hpp"
#include "engine/run/scenario.hpp"
#include "systems/edmd/event_driven_run.hpp"
#include "systems/observables/scattering_angle.hpp"
#include "systems/observables/scattering_scan.hpp"

namespace granflow::scenarios {

namespace {

double impact_ratio(const Config& c, std::size_t member) {
  return c.real("scan.max_ratio") * static_cast<double>(member) / static_cast<double>(c.integer("scan.points") - 1);
}

void build(Run& run) {
  const Config& c = run.config();
  const double r1 = c.real("target.radius"), r2 = c.real("projectile.radius");
  const double reach = r1 + r2;
  if (0.5 + c.real("scan.max_ratio") * reach + r2 >= 1.0)
    throw ConfigError(fmt::format("scan.max_ratio = {} with target.radius = {}: the largest impact parameter puts "
                                  "the projectile outside the unit box",
                                  c.real("scan.max_ratio"), r1));
  const double start_x = 0.5 - reach - 0.05;
  const double speed = c.real("projectile.speed");
  run.initial_state([&](World& world) {
    world.resize(2);
    world.add_component<Mass>().values = {c.real("target.mass"), c.real("projectile.mass")};
    world.add_component<Radius>().values = {r1, r2};
    world.add_component<Position<2>>().values = {Vec<2>(0.5, 0.5),
                                                 Vec<2>(start_x, 0.5 + impact_ratio(c, run.member()) * reach)};
    world.add_component<Velocity<2>>().values = {Vec<2>(0.0, 0.0), Vec<2>(speed, 0.0)};
  });
  Box<2> box;
  box.length.fill(1.0);
  box.periodic.fill(false);
  edmd::AdvanceLimits one_collision;
  one_collision.max_pair_collisions = 1;
  edmd::add_event_driven_gas<2>(run, box, edmd::CollisionParameters::from(c), one_collision, 0.0, false);
  run.observe<ScatteringAngleObserver>(std::make_shared<AtEnd>());
  // Long enough to pass the target, too short to reach the far wall.
  run.stop_at_time((1.0 - r2 - start_x) / speed * 0.99);
  run.finished_reason("the projectile passed the target");
}

std::vector<ScatteringPoint> points_of(const EnsembleResults& results) {
  const Config& c = results.config;
  std::vector<ScatteringPoint> scan;
  for (std::size_t k = 0; k < results.members.size(); ++k) {
    const double ratio = impact_ratio(c, k);
    scan.push_back({ratio, results.members[k].history.at("scattering_angle").back().value.at(0),
                    analytic_scattering_angle(ratio, c.real("target.mass"), c.real("projectile.mass"),
                                              c.real("collision.restitution"))});
  }
  return scan;
}

void reduce(const EnsembleResults& results, H5mdFile& file) {
  const Config& c = results.config;
  write_scattering_scan(file, points_of(results), c.real("target.mass"), c.real("projectile.mass"),
                        c.real("collision.restitution"));
}

void declare_keys(ConfigSchema& s) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  s.real("target.radius", 0.1, 0.0, 0.2, "radius r1 of the large particle at the centre of the unit box", true)
      .real("target.mass", 1e6, 0.0, inf, "mass m1 of the large particle", true)
      .real("projectile.radius", 0.001, 0.0, 0.05, "radius r2 of the small particle", true)
      .real("projectile.mass", 1.0, 0.0, inf, "mass m2 of the small particle", true)
      .real("projectile.speed", 1.0, 0.0, inf, "speed of the small particle along +x", true);
  edmd::CollisionParameters::declare(s, edmd::CollisionParameters{});
  s.integer("scan.points", 51, 2, 100000, "impact parameters from 0 to scan.max_ratio R12")
      .real("scan.max_ratio", 1.1, 0.0, 2.0, "largest impact parameter over R12 = r1 + r2", true);
}

const Scenario scattering{
    .name = "scattering",
    .summary = "scattering angle of a light disk off a heavy one against the impact parameter (EDMD)",
    .default_output = "scattering.h5md",
    .keys = declare_keys,
    .build = build,
    .members = [](const Config& c) { return static_cast<std::size_t>(c.integer("scan.points")); },
    .reduce = reduce,
};

}  // namespace

std::vector<ScatteringPoint> scattering_scan(const Config& config) {
  return points_of(simulate_ensemble(scattering, config));
}

GRANFLOW_REGISTER_SCENARIO(scattering, scattering)

}  // namespace granflow::scenarios
