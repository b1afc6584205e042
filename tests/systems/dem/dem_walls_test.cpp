// The motion laws of a soft-sphere wall: sine moves about its rest
// position; wiggle (LAMMPS's fix wall/gran ... wiggle) starts at rest at its
// rest position and stays between it and rest + 2A. For both the velocity
// is the derivative of the position (central differences, to 1e-8), and the
// watchdog's bounds hold the wall's whole range.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "systems/dem/dem_setup.hpp"
#include "systems/dem/dem_walls.hpp"

namespace granflow::dem {
namespace {

DemWall shaking(WallMotion motion) {
  DemWall w;
  w.rest = 1.0;
  w.amplitude = 0.5;
  w.omega = 2.0 * std::numbers::pi;
  w.motion = motion;
  return w;
}

TEST(DemWalls, WiggleStartsAtRestAndStaysAboveItsRestPosition) {
  const DemWall w = shaking(WallMotion::wiggle);
  EXPECT_EQ(w.position(0.0), 1.0);
  EXPECT_EQ(w.velocity(0.0), 0.0);
  EXPECT_NEAR(w.position(0.5), 2.0, 1e-15);
  EXPECT_NEAR(w.position(0.25), 1.5, 1e-15);
  EXPECT_NEAR(w.velocity(0.25), 0.5 * 2.0 * std::numbers::pi, 1e-12);
  const DemWall s = shaking(WallMotion::sine);
  EXPECT_EQ(s.position(0.0), 1.0);
  EXPECT_NEAR(s.velocity(0.0), std::numbers::pi, 1e-12);
}

TEST(DemWalls, VelocityIsTheDerivativeOfThePosition) {
  for (WallMotion motion : {WallMotion::sine, WallMotion::wiggle}) {
    const DemWall w = shaking(motion);
    const double h = 1e-6;
    for (double t = 0.0; t < 2.0; t += 0.0371) {
      EXPECT_NEAR(w.velocity(t), (w.position(t + h) - w.position(t - h)) / (2.0 * h), 1e-8) << "t = " << t;
      EXPECT_LE(std::abs(w.position(t) - w.centre()), w.amplitude + 1e-15);
    }
  }
}

TEST(DemWalls, TheWatchdogBoundsHoldTheWholeMotion) {
  DemWall floor = shaking(WallMotion::wiggle), ceiling;
  floor.rest = 0.0;
  ceiling.side = +1;
  ceiling.rest = 10.0;
  const auto reach = wall_reach({10.0, 10.0, 10.0}, {true, true, false}, {floor, ceiling});
  EXPECT_EQ(reach.lower[2], 0.0);  // a wiggling floor never goes below its rest position
  floor.motion = WallMotion::sine;
  EXPECT_EQ(wall_reach({10.0, 10.0, 10.0}, {true, true, false}, {floor, ceiling}).lower[2], -0.5);
}

}  // namespace
}  // namespace granflow::dem
