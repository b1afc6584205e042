// Hand-built checks of the event-driven engine: one particle against the
// walls, two particles, many particles (energy conservation) and the
// scattering angle of a hard disk.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "systems/edmd/event_driven_gas.hpp"
#include "tests/systems/edmd/gas_fixture.hpp"
#include "tests/systems/edmd/hand_built_world.hpp"

namespace granflow::edmd {
namespace {

using testing::ParticleSpec;
using V2 = Vec<2>;

CollisionParameters with_restitution(double xi) {
  CollisionParameters p;
  p.restitution = xi;
  p.wall_restitution = xi;
  return p;
}

// --- B.1 one particle -------------------------------------------------------

TEST(AppendixB1, HeadOnWallBounceKeepsSpeed) {
  World world;
  testing::build_world<2>(world, {{V2(0.5, 0.5), V2(1.0, 0.0), 0.01, 1.0}});
  EventDrivenGas<2> gas(world, with_restitution(1.0));
  std::vector<EventRecord> events;
  gas.set_event_observer([&](const EventRecord& r) { events.push_back(r); });
  gas.start(0.0);
  gas.advance(0.6);
  gas.synchronize(gas.time());
  ASSERT_EQ(events.size(), 1u);
  EXPECT_DOUBLE_EQ(events[0].time, 0.49);  // (1 - r - x) / v: time to reach the wall
  EXPECT_EQ(testing::velocity_of<2>(world, 0), V2(-1.0, 0.0));
}

TEST(AppendixB1, ObliqueWallBounceObeysLawOfReflection) {
  World world;
  testing::build_world<2>(world, {{V2(0.5, 0.5), V2(0.8, 0.3), 0.01, 1.0}});
  EventDrivenGas<2> gas(world, with_restitution(1.0));
  gas.start(0.0);
  gas.advance(0.7);  // right wall at t = 0.6125, top wall only at t = 1.63
  gas.synchronize(gas.time());
  const V2 v = testing::velocity_of<2>(world, 0);
  EXPECT_EQ(v, V2(-0.8, 0.3));
  const double incidence = std::atan2(0.3, 0.8), reflection = std::atan2(v.y(), -v.x());
  EXPECT_DOUBLE_EQ(incidence, reflection);
}

TEST(AppendixB1, DiagonalParticleHitsEachWallOnceAndReturns) {
  const double r = 0.01, v0 = 0.7;
  const V2 start(0.3, 0.5);
  World world;
  testing::build_world<2>(world, {{start, V2(v0, v0), r, 1.0}});
  EventDrivenGas<2> gas(world, with_restitution(1.0));
  std::vector<V2> wall_velocities;
  gas.set_event_observer([&](const EventRecord&) { wall_velocities.push_back(gas.velocity(0)); });
  gas.start(0.0);
  // One round trip: the centre travels 2 (L - 2r) along each axis.
  const double period = 2.0 * (1.0 - 2.0 * r) / v0;
  gas.advance(period);
  gas.synchronize(period);
  ASSERT_EQ(wall_velocities.size(), 4u);
  // Each bounce flips one component: right/left and top/bottom walls, once each.
  int flips_x = 0, flips_y = 0;
  V2 previous(v0, v0);
  for (const V2& v : wall_velocities) {
    flips_x += v.x() != previous.x();
    flips_y += v.y() != previous.y();
    previous = v;
  }
  EXPECT_EQ(flips_x, 2);
  EXPECT_EQ(flips_y, 2);
  EXPECT_NEAR((testing::position_of<2>(world, 0) - start).norm(), 0.0, 1e-12);
  EXPECT_EQ(testing::velocity_of<2>(world, 0), V2(v0, v0));
}

TEST(AppendixB1, FullyInelasticWallStopsTheParticle) {
  World world;
  testing::build_world<2>(world, {{V2(0.5, 0.5), V2(1.0, 0.4), 0.01, 1.0}});
  EventDrivenGas<2> gas(world, with_restitution(0.0));
  gas.start(0.0);
  gas.advance(5.0);
  gas.synchronize(gas.time());
  EXPECT_EQ(testing::velocity_of<2>(world, 0), V2(0.0, 0.0));
  EXPECT_EQ(gas.statistics().wall_collisions, 1u);
}

// --- B.2 two particles ------------------------------------------------------

TEST(AppendixB2, HeadOnElasticPairBouncesBack) {
  World world;
  testing::build_world<2>(world, {{V2(0.3, 0.5), V2(1.0, 0.0), 0.05, 1.0}, {V2(0.7, 0.5), V2(-1.0, 0.0), 0.05, 1.0}});
  EventDrivenGas<2> gas(world, with_restitution(1.0));
  gas.start(0.0);
  gas.advance(0.2);  // contact at t = 0.15
  gas.synchronize(gas.time());
  EXPECT_EQ(gas.statistics().pair_collisions, 1u);
  // Exact up to the rounding of (dv.dx) dx / |dx|^2.
  EXPECT_NEAR((testing::velocity_of<2>(world, 0) - V2(-1.0, 0.0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((testing::velocity_of<2>(world, 1) - V2(1.0, 0.0)).norm(), 0.0, 1e-15);
}

TEST(AppendixB2, ImpactParameterOverRootTwoGivesRightAngle) {
  const double r = 0.05, b = 2 * r / std::numbers::sqrt2;
  World world;
  testing::build_world<2>(world, {{V2(0.3, 0.5 - b / 2), V2(1.0, 0.0), r, 1.0},
                                  {V2(0.7, 0.5 + b / 2), V2(-1.0, 0.0), r, 1.0}});
  EventDrivenGas<2> gas(world, with_restitution(1.0));
  gas.start(0.0);
  gas.advance(0.25);
  gas.synchronize(gas.time());
  ASSERT_EQ(gas.statistics().pair_collisions, 1u);
  for (std::uint32_t id : {0u, 1u}) {
    const V2 before = id == 0 ? V2(1.0, 0.0) : V2(-1.0, 0.0);
    const V2 after = testing::velocity_of<2>(world, id);
    EXPECT_NEAR(after.norm(), 1.0, 1e-14);
    EXPECT_NEAR(after.dot(before), 0.0, 1e-14) << "particle " << id << " leaves at " << after.transpose();
  }
}

TEST(AppendixB2, HeadOnFullyInelasticPairStops) {
  World world;
  testing::build_world<2>(world, {{V2(0.3, 0.5), V2(1.0, 0.0), 0.05, 1.0}, {V2(0.7, 0.5), V2(-1.0, 0.0), 0.05, 1.0}});
  EventDrivenGas<2> gas(world, with_restitution(0.0));
  gas.start(0.0);
  gas.advance(5.0);
  gas.synchronize(gas.time());
  // The pair stays in contact; a rounding-level approach speed left by the
  // first collision may make it collide again at the same instant.
  EXPECT_GE(gas.statistics().pair_collisions, 1u);
  EXPECT_NEAR(testing::velocity_of<2>(world, 0).norm(), 0.0, 1e-15);
  EXPECT_NEAR(testing::velocity_of<2>(world, 1).norm(), 0.0, 1e-15);
}

// --- B.3 many particles: elastic energy conservation -----------------------

template <int D>
void expect_energy_conserved(bool periodic) {
  World world;
  testing::fill_gas<D>(world, 1000, testing::radius_for_packing_fraction<D>(1000, 0.1), periodic, 3);
  EventDrivenGas<D> gas(world, with_restitution(1.0));
  gas.start(0.0);
  const double before = gas.kinetic_energy();
  AdvanceLimits limits;
  limits.max_pair_collisions = 1'000'000;
  ASSERT_EQ(gas.advance(std::numeric_limits<double>::infinity(), limits), StopReason::collision_limit);
  gas.synchronize(gas.time());
  const double after = gas.kinetic_energy();  // recomputed from the velocities
  EXPECT_LT(std::abs(after - before) / before, 1e-12) << "before " << before << " after " << after;
}

TEST(AppendixB3, ElasticEnergyConservedOverAMillionCollisions2DReflecting) { expect_energy_conserved<2>(false); }
TEST(AppendixB3, ElasticEnergyConservedOverAMillionCollisions3DPeriodic) { expect_energy_conserved<3>(true); }

// --- B.4 scattering angle ---------------------------------------------------

double scattering_angle(double impact_over_contact) {
  const double r1 = 0.1, r2 = 0.001, contact = r1 + r2;
  World world;
  testing::build_world<2>(world, {{V2(0.5, 0.5), V2(0.0, 0.0), r1, 1e6},
                                  {V2(0.2, 0.5 + impact_over_contact * contact), V2(1.0, 0.0), r2, 1.0}});
  EventDrivenGas<2> gas(world, with_restitution(1.0));
  double collision_time = -1;
  gas.set_event_observer([&](const EventRecord& r) {
    if (collision_time < 0 && r.second != EventRecord::wall_partner) collision_time = r.time;
  });
  gas.start(0.0);
  gas.advance(0.35);  // contact before t = 0.3; no wall reachable before 0.35
  gas.synchronize(gas.time());
  if (collision_time < 0) return 0.0;
  const V2 after = testing::velocity_of<2>(world, 1);
  return std::acos(std::clamp(after.x() / after.norm(), -1.0, 1.0));
}

TEST(AppendixB4, ScatteringAngleFollowsHardSphereLaw) {
  for (int k = 0; k <= 20; ++k) {
    const double ratio = k / 20.0 * 0.999;
    const double expected = std::numbers::pi - 2.0 * std::asin(ratio);
    // The target's finite mass (10^6) changes the angle by O(1e-6).
    EXPECT_NEAR(scattering_angle(ratio), expected, 1e-5) << "b/R12 = " << ratio;
  }
  EXPECT_EQ(scattering_angle(1.05), 0.0);  // misses
}

}  // namespace
}  // namespace granflow::edmd
