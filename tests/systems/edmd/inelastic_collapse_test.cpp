// Inelastic collapse is detected and reported (never a hang), and the TC
// model cures it.

#include <gtest/gtest.h>

#include "systems/edmd/event_driven_gas.hpp"
#include "tests/systems/edmd/hand_built_world.hpp"

namespace granflow::edmd {
namespace {

using V2 = Vec<2>;

// Ten disks in a row, the end ones moving inward: below a critical
// restitution (about 0.4 for ten particles in one dimension) they collide
// infinitely often in finite time (Bernu & Mazighi 1990; McNamara & Young
// 1994). A common sideways drift keeps the kinetic energy finite, so the
// collision rate runs away at fixed thermal speed. (With three disks the
// threshold is 7 - 4 sqrt(3) = 0.072 and round-off often ends the sequence
// first, so that case does not make a reliable test.)
void build_collapsing_row(World& world) {
  std::vector<testing::ParticleSpec<2>> row;
  for (int k = 0; k < 10; ++k)
    row.push_back({V2(0.1 + 0.045 * k, 0.5), V2(k == 0 ? 1.0 : k == 9 ? -1.0 : 0.0, 0.3), 0.02, 1.0});
  testing::build_world<2>(world, row, true);
}

TEST(InelasticCollapse, IsDetectedAndExplained) {
  World world;
  build_collapsing_row(world);
  CollisionParameters parameters;
  parameters.restitution = 0.3;
  EventDrivenGas<2> gas(world, parameters);
  gas.start(0.0);
  EXPECT_EQ(gas.advance(10.0), StopReason::collapse);
  EXPECT_NE(gas.collapse_message().find("inelastic collapse"), std::string::npos);
  EXPECT_NE(gas.collapse_message().find("collision.contact_time"), std::string::npos) << gas.collapse_message();
  EXPECT_LT(gas.time(), 1.0);
}

TEST(InelasticCollapse, TcModelLetsTheRunContinue) {
  World world;
  build_collapsing_row(world);
  CollisionParameters parameters;
  parameters.restitution = 0.3;
  parameters.contact_time = 1e-4;
  EventDrivenGas<2> gas(world, parameters);
  gas.start(0.0);
  EXPECT_EQ(gas.advance(10.0), StopReason::reached_time);
  EXPECT_LT(gas.statistics().pair_collisions, 10000u);
}

}  // namespace
}  // namespace granflow::edmd
