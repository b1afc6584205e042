// Inelastic collapse is detected and reported (never a hang), and the TC
// model cures it.

#include <gtest/gtest.h>

#include "systems/edmd/event_driven_gas.hpp"
#include "tests/systems/edmd/hand_built_world.hpp"

namespace granflow::edmd {
namespace {

using V2 = Vec<2>;

// Three disks on a line, the outer two closing in on the middle one: for
// restitution below 7 - 4 sqrt(3) = 0.072 they collide infinitely often in
// finite time (McNamara & Young 1994). A common sideways drift keeps the
// kinetic energy finite, so the collision rate runs away at fixed thermal speed.
// (Just below the threshold, at 0.05, round-off ends the sequence after ~100
// collisions with relative speeds of 1e-29; at 0.02 it runs away.)
void build_collapsing_trio(World& world) {
  testing::build_world<2>(world, {{V2(0.3, 0.5), V2(1.0, 0.3), 0.02, 1.0},
                                  {V2(0.45, 0.5), V2(0.0, 0.3), 0.02, 1.0},
                                  {V2(0.7, 0.5), V2(-1.0, 0.3), 0.02, 1.0}},
                          true);
}

TEST(InelasticCollapse, IsDetectedAndExplained) {
  World world;
  build_collapsing_trio(world);
  CollisionParameters parameters;
  parameters.restitution = 0.02;
  EventDrivenGas<2> gas(world, parameters);
  gas.start(0.0);
  EXPECT_EQ(gas.advance(10.0), StopReason::collapse);
  EXPECT_NE(gas.collapse_message().find("inelastic collapse"), std::string::npos);
  EXPECT_NE(gas.collapse_message().find("collision.contact_time"), std::string::npos) << gas.collapse_message();
  EXPECT_LT(gas.time(), 1.0);
}

TEST(InelasticCollapse, TcModelLetsTheRunContinue) {
  World world;
  build_collapsing_trio(world);
  CollisionParameters parameters;
  parameters.restitution = 0.02;
  parameters.contact_time = 1e-4;
  EventDrivenGas<2> gas(world, parameters);
  gas.start(0.0);
  EXPECT_EQ(gas.advance(10.0), StopReason::reached_time);
  EXPECT_LT(gas.statistics().pair_collisions, 10000u);
}

}  // namespace
}  // namespace granflow::edmd
