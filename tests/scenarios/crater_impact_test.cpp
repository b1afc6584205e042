// Crater impact: every pair collision conserves
// momentum, every wall collision reverses the normal velocity and scales the
// velocity by the wall restitution, and the kinetic energy lost equals the dissipation summed over
// collisions, both as the engine reports it and as recomputed here from the
// velocities before and after each collision.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "systems/edmd/crater_bed.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "tests/scenario_schema.hpp"

namespace granflow::scenarios {
namespace {

using edmd::build_crater;

TEST(CraterImpact, CollisionsConserveMomentumAndAccountForEveryJoule) {
  Config config(scenario_schema("crater_impact"));
  config.set("system.count", std::int64_t{1000});
  World world;
  build_crater(world, config);
  const double energy0 = total_kinetic_energy<2>(world);
  const double momentum_scale = config.real("projectile.mass_ratio") * config.real("projectile.speed");

  // Unsorted storage, so storage index = particle id = the ids events report.
  edmd::EventDrivenGas<2> gas(world, edmd::CollisionParameters::from(config), false);
  std::vector<Vec<2>> known = world.component<Velocity<2>>().values;
  const auto& mass = world.component<Mass>();
  const double wall_restitution = config.real("collision.wall_restitution");
  double recomputed_loss = 0.0, worst_pair = 0.0, worst_wall = 0.0;
  std::size_t pairs = 0, walls = 0;
  gas.set_event_observer([&](const edmd::EventRecord& e) {
    const std::uint32_t i = e.first;
    const Vec<2> vi = gas.velocity(i);
    if (e.second == edmd::EventRecord::wall_partner) {
      // The normal component is reversed and the whole
      // velocity scaled by the wall restitution (tangential part included),
      // or by 1 within the TC model's contact time.
      double best = INFINITY;
      for (int axis = 0; axis < 2; ++axis)
        for (double restitution : {wall_restitution, 1.0}) {
          Vec<2> reflected = known[i];
          reflected[axis] = -reflected[axis];
          best = std::min(best, (vi - restitution * reflected).norm() / known[i].norm());
        }
      worst_wall = std::max(worst_wall, best);
      recomputed_loss += 0.5 * mass[i] * (known[i].squaredNorm() - vi.squaredNorm());
      known[i] = vi;
      ++walls;
      return;
    }
    const std::uint32_t j = e.second;
    const Vec<2> vj = gas.velocity(j);
    const Vec<2> dp = mass[i] * (vi - known[i]) + mass[j] * (vj - known[j]);
    worst_pair = std::max(worst_pair, dp.norm() / momentum_scale);
    recomputed_loss += 0.5 * mass[i] * (known[i].squaredNorm() - vi.squaredNorm()) +
                       0.5 * mass[j] * (known[j].squaredNorm() - vj.squaredNorm());
    known[i] = vi;
    known[j] = vj;
    ++pairs;
  });
  gas.start(0.0);
  edmd::AdvanceLimits limits;
  limits.min_kinetic_energy = 0.1 * energy0;
  const auto reason = gas.advance(config.real("run.t_stop"), limits);
  ASSERT_EQ(reason, edmd::StopReason::energy_limit) << gas.collapse_message();
  gas.synchronize(gas.time());
  ASSERT_GT(pairs, 1000u);
  ASSERT_GT(walls, 0u);

  const double energy = total_kinetic_energy<2>(world);
  const auto& stats = gas.statistics();
  // Round-off of a few hundred thousand updates of O(1) energies.
  EXPECT_NEAR((energy0 - energy) / energy0, (stats.dissipated_energy + stats.wall_dissipated_energy) / energy0, 1e-10);
  EXPECT_NEAR(recomputed_loss / energy0, (energy0 - energy) / energy0, 1e-10);
  EXPECT_LT(worst_pair, 1e-13) << pairs << " pair collisions";
  EXPECT_LT(worst_wall, 1e-15) << walls << " wall collisions";
  // The velocities the events reported are the ones the gas ends with.
  for (std::size_t i = 0; i < world.size(); ++i) EXPECT_EQ(known[i], world.component<Velocity<2>>()[i]) << i;
}

TEST(CraterImpact, DenseBedIsPlacedWithoutOverlap) {
  Config config(scenario_schema("crater_impact"));
  config.set("system.count", std::int64_t{2000});
  World world;
  build_crater(world, config);
  const auto& x = world.component<Position<2>>();
  const auto& r = world.component<Radius>();
  double area = 0.0;
  for (std::size_t i = 0; i + 1 < world.size(); ++i) {
    area += std::numbers::pi * r[i] * r[i];
    EXPECT_LE(x[i].y() + r[i], 0.5 + 1e-12);
    EXPECT_GE(x[i].y() - r[i], -1e-12);
    EXPECT_GE(x[i].x() - r[i], -1e-12);
    EXPECT_LE(x[i].x() + r[i], 1.0 + 1e-12);
    for (std::size_t j = i + 1; j < world.size(); ++j)
      ASSERT_GE((x[i] - x[j]).norm(), (r[i] + r[j]) * (1 - 1e-12)) << i << " " << j;
  }
  EXPECT_NEAR(area / 0.5, 0.5, 1e-12);
}

}  // namespace
}  // namespace granflow::scenarios
