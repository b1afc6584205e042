#include "scenarios/scattering.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>

#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/h5md_file.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::scenarios {

const ConfigSchema& scattering_schema() {
  static const ConfigSchema schema = [] {
    constexpr double inf = std::numeric_limits<double>::infinity();
    ConfigSchema s;
    s.choice("scenario", "scattering", {"scattering"}, "scenario name")
        .real("target.radius", 0.1, 0.0, 0.2, "radius r1 of the large particle at the centre of the unit box", true)
        .real("target.mass", 1e6, 0.0, inf, "mass m1 of the large particle", true)
        .real("projectile.radius", 0.001, 0.0, 0.05, "radius r2 of the small particle", true)
        .real("projectile.mass", 1.0, 0.0, inf, "mass m2 of the small particle", true)
        .real("projectile.speed", 1.0, 0.0, inf, "speed of the small particle along +x", true)
        .real("collision.restitution", 1.0, 0.0, 1.0, "normal restitution coefficient xi")
        .integer("scan.points", 51, 2, 100000, "impact parameters from 0 to scan.max_ratio R12")
        .real("scan.max_ratio", 1.1, 0.0, 2.0, "largest impact parameter over R12 = r1 + r2", true);
    return s;
  }();
  return schema;
}

double analytic_scattering_angle(double ratio, double m1, double m2, double restitution) {
  if (ratio >= 1.0) return 0.0;
  // Unit vector from the small particle's centre to the large one's at contact.
  const double nx = std::sqrt(1.0 - ratio * ratio), ny = -ratio;
  const double push = (1.0 + restitution) * m1 / (m1 + m2) * nx;  // (v . n) with v = (1, 0)
  const double vx = 1.0 - push * nx, vy = -push * ny;
  return std::atan2(std::abs(vy), vx);
}

std::vector<ScatteringPoint> scattering_scan(const Config& config) {
  const double r1 = config.real("target.radius"), r2 = config.real("projectile.radius");
  const double m1 = config.real("target.mass"), m2 = config.real("projectile.mass");
  const double speed = config.real("projectile.speed");
  const double xi = config.real("collision.restitution");
  const auto points = static_cast<std::size_t>(config.integer("scan.points"));
  const double max_ratio = config.real("scan.max_ratio");
  const double reach = r1 + r2;
  if (0.5 + max_ratio * reach + r2 >= 1.0)
    throw ConfigError(fmt::format("scan.max_ratio = {} with target.radius = {}: the largest impact parameter puts "
                                  "the projectile outside the unit box",
                                  max_ratio, r1));
  std::vector<ScatteringPoint> scan(points);
  tbb::parallel_for(std::size_t{0}, points, [&](std::size_t k) {
    const double ratio = max_ratio * static_cast<double>(k) / static_cast<double>(points - 1);
    World world(2);
    Box<2> box;
    box.length.fill(1.0);
    box.periodic.fill(false);
    world.emplace_resource<Box<2>>(box);
    world.add_component<Mass>().values = {m1, m2};
    world.add_component<Radius>().values = {r1, r2};
    const double start_x = 0.5 - reach - 0.05;
    world.add_component<Position<2>>().values = {Vec<2>(0.5, 0.5), Vec<2>(start_x, 0.5 + ratio * reach)};
    world.add_component<Velocity<2>>().values = {Vec<2>(0.0, 0.0), Vec<2>(speed, 0.0)};
    edmd::CollisionParameters parameters;
    parameters.restitution = xi;
    edmd::EventDrivenGas<2> gas(world, parameters, false);
    gas.start(0.0);
    edmd::AdvanceLimits limits;
    limits.max_pair_collisions = 1;
    // Long enough to pass the target, too short to reach the far wall.
    gas.advance((1.0 - r2 - start_x) / speed * 0.99, limits);
    const Vec<2> after = gas.velocity(1);
    scan[k] = {ratio, std::atan2(std::abs(after.y()), after.x()), analytic_scattering_angle(ratio, m1, m2, xi)};
  });
  return scan;
}

int run_scattering(const Config& config, const RunOptions& options) {
  const std::string output_path = options.output_path.empty() ? "scattering.h5" : options.output_path;
  H5mdFile file(output_path, "scattering");
  file.write_parameters(config);
  const auto scan = scattering_scan(config);
  std::vector<double> ratio, angle, analytic;
  double worst = 0.0;
  for (const auto& p : scan) {
    ratio.push_back(p.impact_ratio);
    angle.push_back(p.angle);
    analytic.push_back(p.analytic);
    worst = std::max(worst, std::abs(p.angle - p.analytic));
  }
  file.write_observable_constant("impact_parameter_ratio", ratio);
  file.write_observable_constant("scattering_angle", angle);
  file.write_observable_constant("scattering_angle_analytic", analytic);
  file.write_attribute("/observables", "largest_deviation_rad", worst);
  file.write_attribute("/observables", "stop_reason", "scan complete");
  file.finish();
  spdlog::info("{} impact parameters, largest deviation from the analytic angle {:.3g} rad; wrote {}", scan.size(),
               worst, output_path);
  return 0;
}

}  // namespace granflow::scenarios
