// Streaming between SRD walls against closed forms: the exact time a
// particle under gravity meets a fixed wall, the energy of a particle
// bouncing under gravity between fixed walls (conserved: the reflections
// reverse velocities, the flight is exact), the meeting time with a moving
// wall against a brute-force root, and the reflection rules.

#include <gtest/gtest.h>

#include <cmath>

#include "engine/rng.hpp"
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
