// Streaming between SRD walls against closed forms: the exact time a
// particle under gravity meets a fixed wall, the energy of a particle
// bouncing under gravity between fixed walls (conserved: the reflections
// reverse velocities, the flight is exact), the meeting time with a moving
// wall against a brute-force root, and the reflection rules.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/core/rng.hpp"
#include "systems/srd/srd_walls.hpp"

namespace granflow::srd {
namespace {

Wall floor_wall(WallKind kind) {
  Wall w;
  w.axis = 2;
  w.side = -1;
  w.kind = kind;
  return w;
}

Wall ceiling_wall(WallKind kind, double height) {
  Wall w = floor_wall(kind);
  w.side = +1;
  w.rest = height;
  return w;
}

TEST(SrdWalls, HitTimeUnderGravityIsTheRootOfTheFlight) {
  const Wall floor = floor_wall(WallKind::no_slip);
  // z = 1 - 2 s - s^2 / 2 = 0 at s = sqrt(6) - 2.
  EXPECT_NEAR(wall_hit_time(floor, 1.0, -2.0, -1.0, 0.0, 1.0), std::sqrt(6.0) - 2.0, 1e-15);
  // Thrown up at 1 from z = 0.5 with g = -1: back at the floor at s = 1 + sqrt(2).
  EXPECT_NEAR(wall_hit_time(floor, 0.5, 1.0, -1.0, 0.0, 5.0), 1.0 + std::sqrt(2.0), 1e-14);
  EXPECT_LT(wall_hit_time(floor, 0.5, 1.0, -1.0, 0.0, 2.0), 0.0);  // not yet within 2
  // Leaving the floor after a reflection (on it, moving up): no hit at s = 0.
  EXPECT_LT(wall_hit_time(floor, 0.0, 1.0, 0.0, 0.0, 5.0), 0.0);
  const Wall ceiling = ceiling_wall(WallKind::slip, 3.0);
  EXPECT_NEAR(wall_hit_time(ceiling, 1.0, 4.0, 0.0, 0.0, 1.0), 0.5, 1e-15);
  EXPECT_LT(wall_hit_time(ceiling, 1.0, -4.0, 0.0, 0.0, 1.0), 0.0);
}

TEST(SrdWalls, ReflectionRulesRelativeToTheMovingWall) {
  Wall wall = floor_wall(WallKind::no_slip);
  wall.amplitude = 0.5;
  wall.omega = 2.0;  // velocity at t = 0: A omega = 1
  double v[3] = {0.3, -0.2, -1.5};
  reflect<3>(wall, 0.0, v);
  EXPECT_DOUBLE_EQ(v[0], -0.3);
  EXPECT_DOUBLE_EQ(v[1], 0.2);
  EXPECT_DOUBLE_EQ(v[2], 2.0 * 1.0 + 1.5);
  wall.kind = WallKind::slip;
  double w[3] = {0.3, -0.2, -1.5};
  reflect<3>(wall, 0.0, w);
  EXPECT_DOUBLE_EQ(w[0], 0.3);
  EXPECT_DOUBLE_EQ(w[1], -0.2);
  EXPECT_DOUBLE_EQ(w[2], 3.5);
  // Kinetic energy gained: (2u - v)^2/2 - v^2/2 = 2 u (u - v).
  EXPECT_NEAR(0.5 * (w[2] * w[2] - 1.5 * 1.5), 2.0 * 1.0 * (1.0 + 1.5), 1e-14);
}

TEST(SrdWalls, BouncingUnderGravityBetweenFixedWallsConservesEnergy) {
  for (const WallKind kind : {WallKind::no_slip, WallKind::slip}) {
    const Wall walls[2] = {floor_wall(kind), ceiling_wall(kind, 4.0)};
    const double g[3] = {0.0, 0.0, -1.0};
    Philox random(1, 2, 3, static_cast<int>(kind));
    double x[3] = {0.3, 0.7, 2.0}, v[3];
    for (double& component : v) component = 2.0 * random.normal();
    const auto energy = [&] { return 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - g[2] * x[2]; };
    const double e0 = energy();
    int reflections = 0;
    for (int step = 0; step < 20000; ++step) {
      reflections += stream_between_walls<3>(x, v, g, 0.1 * step, 0.1, walls, 2);
      ASSERT_GE(x[2], 0.0);
      ASSERT_LE(x[2], 4.0);
    }
    EXPECT_GT(reflections, 100);
    EXPECT_NEAR(energy(), e0, 1e-10 * e0) << "kind " << static_cast<int>(kind);
  }
}

// Under gravity over a vibrating floor a particle's energy v^2/2 - g z
// changes only when it meets the moving floor, by the work that reflection
// reports; over a resting floor not at all.
TEST(SrdWalls, OverAVibratingFloorEnergyChangesOnlyByTheFloorsWork) {
  for (const WallKind kind : {WallKind::no_slip, WallKind::slip}) {
    Wall floor = floor_wall(kind);
    floor.amplitude = 0.2;
    floor.omega = 3.0;
    const Wall walls[2] = {floor, ceiling_wall(kind, 6.0)};
    const double g[3] = {0.0, 0.0, -1.0};
    Philox random(7, 8, 9, static_cast<int>(kind));
    double x[3] = {0.3, 0.7, 2.0}, v[3];
    for (double& component : v) component = random.normal();
    const auto energy = [&] { return 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - g[2] * x[2]; };
    int floor_hits = 0;
    double total_work = 0.0;
    const double e0 = energy();
    for (int step = 0; step < 20000; ++step) {
      const double before = energy();
      double work = 0.0;
      const int hits = stream_between_walls<3>(x, v, g, 0.05 * step, 0.05, walls, 2, &work);
      const double t = 0.05 * (step + 1);
      ASSERT_GE(x[2], floor.position(t) - 1e-12);
      ASSERT_LE(x[2], 6.0);
      // Round-off of the flight: a few ulps of the energy per step.
      ASSERT_NEAR(energy() - before, work, 1e-11 * std::max(1.0, before)) << "step " << step;
      if (hits == 0) {
        ASSERT_EQ(work, 0.0);
      }
      floor_hits += work != 0.0;
      total_work += work;
    }
    EXPECT_GT(floor_hits, 100) << "kind " << static_cast<int>(kind);
    EXPECT_NEAR(energy() - e0, total_work, 1e-8 * std::max(1.0, e0));
  }
}

TEST(SrdWalls, ASlabForceActsOnlyInsideItsSlab) {
  BodyForce<3> force;
  force.acceleration[0] = 0.5;
  force.slab_axis = 1;
  force.from = 2.0;
  force.to = 4.0;
  EXPECT_TRUE(force.any());
  const double inside[3] = {9.0, 2.0, 0.0}, upper_edge[3] = {0.0, 4.0, 0.0}, below[3] = {0.0, 1.999, 0.0};
  EXPECT_TRUE(force.acts_at(inside));
  EXPECT_FALSE(force.acts_at(upper_edge));
  EXPECT_FALSE(force.acts_at(below));
  force.slab_axis = -1;
  EXPECT_TRUE(force.acts_at(below));
  EXPECT_FALSE(BodyForce<3>{}.any());
}

TEST(SrdWalls, MeetingAMovingWallAgreesWithABruteForceRoot) {
  Wall wall = floor_wall(WallKind::slip);
  wall.amplitude = 0.3;
  wall.omega = 5.0;
  int hits = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Philox random(4, 5, 6, static_cast<std::uint64_t>(trial));
    const double t0 = 3.0 * random.uniform();
    const double x = wall.position(t0) + 0.5 * random.uniform(), v = -2.0 * random.uniform(), g = -1.0;
    const double span = 0.5;
    const double s = wall_hit_time(wall, x, v, g, t0, span);
    // The first sign change of the depth on a fine grid, then its bisection.
    double found = -1.0;
    constexpr int grid = 100000;
    for (int k = 1; k <= grid; ++k) {
      const double t = span * k / grid;
      if (depth(wall, x + v * t + 0.5 * g * t * t, t0 + t) <= 0.0) {
        found = t;
        break;
      }
    }
    if (found < 0.0) {
      EXPECT_LT(s, 0.0) << "trial " << trial;
      continue;
    }
    ++hits;
    EXPECT_NEAR(s, found, 1.0 * span / grid) << "trial " << trial;
    EXPECT_NEAR(depth(wall, x + v * s + 0.5 * g * s * s, t0 + s), 0.0, 1e-12);
  }
  EXPECT_GT(hits, 50);
  EXPECT_LT(hits, 200);
}

}  // namespace
}  // namespace granflow::srd
