// The soft-sphere watchdog and the stability limits behind the time step:
// a sphere driven through a wall, or with a position that is not finite
// (which forces a neighbour-list build), stops the run at the build with a
// diagnosis naming it; an energy ledger that no longer
// balances stops it, one that balances does not; a closed axis without a
// wall on each side is refused. The contact time scales agree with the
// spring-dashpot formula and, for Hertz, with a direct integration of
// m delta'' = -k delta^(3/2) (a slower reference, to 0.5 %).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/input_error.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/dem/dem_setup.hpp"
#include "systems/dem/dem_watchdog.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/stability_limits.hpp"
#include "systems/dem/velocity_verlet.hpp"

namespace granflow::dem {
namespace {

// One sphere above a floor at z = 0 in a closed 10^3 box, advanced by the drift alone.
struct OneSphere {
  World world;
  OneSphere() {
    world.resize(1);
    world.emplace_resource<Clock>();
    world.emplace_resource<RunControl>();
    world.add_component<Position<3>>()[0] = Vec<3>(5.0, 5.0, 1.0);
    world.add_component<Velocity<3>>()[0] = Vec<3>(0.0, 0.0, 0.0);
    world.add_component<Force<3>>()[0] = Vec<3>(0.0, 0.0, 0.0);
    world.add_component<Mass>().values.assign(1, 1.0);
    world.add_component<Radius>().values.assign(1, 0.5);
    world.add_component<ParticleId>().values.assign(1, 7u);
    auto& box = world.emplace_resource<Box<3>>();
    box.length = {10.0, 10.0, 10.0};
    std::vector<DemWall> walls;
    for (int axis = 0; axis < 3; ++axis)
      for (int side : {-1, +1}) {
        DemWall w;
        w.axis = axis;
        w.side = side;
        w.rest = side < 0 ? 0.0 : 10.0;
        walls.push_back(w);
      }
    auto& watch = world.emplace_resource<DemWatch<3>>(wall_reach(box.length, box.periodic, walls));
    watch.advice = "ADVICE";
    world.emplace_resource<NeighbourList<3>>().skin = 0.2;
  }
  const RunControl& control() { return world.resource<RunControl>(); }
};

TEST(DemWatchdog, ASphereThroughTheFloorStopsTheRunAtTheNextBuild) {
  OneSphere s;
  s.world.component<Velocity<3>>()[0] = Vec<3>(0.0, 0.0, -30.0);
  DemKickDrift<3> drift(0.01);
  DemNeighbourList<3> lists;
  for (int step = 0; step < 3; ++step) {
    drift.run(s.world);
    lists.run(s.world);  // the sphere moves 0.3 a step: a build every step
  }
  EXPECT_FALSE(s.control().stop) << "at z = 0.1 the centre is still above the floor";
  drift.run(s.world);
  lists.run(s.world);
  ASSERT_TRUE(s.control().failed);
  EXPECT_NE(s.control().reason.find("sphere 7 went through a wall: z = -0.2"), std::string::npos) << s.control().reason;
  EXPECT_NE(s.control().reason.find("ADVICE"), std::string::npos);
  EXPECT_NE(s.control().reason.find("t = 0.04"), std::string::npos) << s.control().reason;
}

TEST(DemWatchdog, APositionThatIsNotFiniteForcesABuildThatStopsTheRun) {
  OneSphere s;
  DemNeighbourList<3> lists;
  lists.run(s.world);
  ASSERT_FALSE(s.control().stop);
  s.world.component<Force<3>>()[0] = Vec<3>(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  DemKickDrift<3>(0.01).run(s.world);
  EXPECT_TRUE(DemNeighbourList<3>::moved_too_far(s.world, s.world.resource<NeighbourList<3>>()));
  lists.run(s.world);
  ASSERT_TRUE(s.control().failed);
  EXPECT_NE(s.control().reason.find("sphere 7 has a position that is not finite (x = nan)"), std::string::npos)
      << s.control().reason;
}

// The energy watch fed the values observe_dem_energy would give.
struct Ledger {
  World world;
  DemEnergyWatch<3> watch;
  Ledger() {
    world.emplace_resource<Clock>();
    world.emplace_resource<RunControl>();
    world.emplace_resource<DemWatch<3>>();
    auto& store = world.emplace_resource<ObservableStore>();
    for (const char* name :
         {"kinetic_energy", "potential_energy", "elastic_energy", "energy_injected", "energy_dissipated"})
      store.declare(name);
  }
  void observe(double kinetic, double potential, double elastic, double injected, double dissipated) {
    auto& store = world.resource<ObservableStore>();
    store.set("kinetic_energy", kinetic);
    store.set("potential_energy", potential);
    store.set("elastic_energy", elastic);
    store.set("energy_injected", injected);
    store.set("energy_dissipated", dissipated);
    watch.run(world);
  }
  const RunControl& control() { return world.resource<RunControl>(); }
};

TEST(DemWatchdog, ABalancedLedgerPassesAndOneThatCreatesEnergyStops) {
  Ledger ok;
  ok.observe(10.0, 50.0, 0.0, 0.0, 0.0);
  ok.observe(200.0, 80.0, 1.0, 400.0, 178.0);  // E - E0 = 221 against 222: 1 off of 819 turned over
  ok.observe(5.0, 52.0, 0.0, 400.0, 390.0);    // -3 against 10: 13 off of 807
  EXPECT_FALSE(ok.control().stop) << ok.control().reason;

  Ledger bad;
  bad.observe(53.0, 0.0, 0.0, 0.0, 0.0);
  bad.observe(6.6e11, 1.0, 0.0, 10.0, 5.0);
  ASSERT_TRUE(bad.control().failed);
  EXPECT_NE(bad.control().reason.find("the step created"), std::string::npos) << bad.control().reason;

  Ledger nan;
  nan.observe(1.0, 0.0, 0.0, 0.0, 0.0);
  nan.observe(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, 0.0, 0.0);
  ASSERT_TRUE(nan.control().failed);
  EXPECT_NE(nan.control().reason.find("not finite"), std::string::npos);
}

TEST(DemWatchdog, ARestoredWatchKeepsItsStart) {
  Ledger first;
  first.observe(10.0, 50.0, 0.0, 0.0, 0.0);
  Ledger resumed;
  resumed.watch.restore_state(first.watch.save_state());
  resumed.observe(10.0, 50.0, 0.0, 1e6, 0.0);  // a million injected and nothing to show for it
  EXPECT_TRUE(resumed.control().failed);
}

TEST(DemWatchdog, AClosedAxisNeedsAWallOnEachSide) {
  DemWall floor;
  floor.axis = 2;
  floor.side = -1;
  try {
    wall_reach({10.0, 10.0, 10.0}, {true, true, false}, {floor});
    FAIL() << "a box open at the top was accepted";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("closed along z but has no wall on its upper side"), std::string::npos)
        << error.what();
  }
  DemWall ceiling = floor;
  ceiling.side = +1;
  ceiling.rest = 10.0;
  floor.amplitude = 0.5;
  const auto reach = wall_reach({10.0, 10.0, 10.0}, {true, true, false}, {floor, ceiling});
  EXPECT_EQ(reach.lower[2], -0.5);
  EXPECT_EQ(reach.upper[2], 10.0);
  EXPECT_TRUE(std::isinf(reach.lower[0]) && std::isinf(reach.upper[1]));
}

TEST(StabilityLimits, SpringDashpotScalesFollowTheLaw) {
  ContactLaw law;
  law.stiffness = 2e4;
  law.damping = ContactLaw::lsd_damping_factor(0.7);
  const ContactScales s = contact_scales(law, 0.5, 10.0, 0.0);
  EXPECT_DOUBLE_EQ(s.duration, law.contact_time(0.5));
  EXPECT_DOUBLE_EQ(s.spring_time, std::numbers::pi * std::sqrt(0.5 / 2e4));
  EXPECT_DOUBLE_EQ(s.damping_time, 0.5 / law.gamma(0.5));
  EXPECT_DOUBLE_EQ(s.overlap, 10.0 * std::sqrt(0.5 / 2e4));
  EXPECT_FALSE(s.overdamped);
  // The default step stays t_c / 50 wherever the dashpot is slow.
  EXPECT_DOUBLE_EQ(s.default_step(), law.contact_time(0.5) / 50.0);
  law.damping = 2.0;  // gamma = 2 sqrt(m k): critical
  EXPECT_TRUE(contact_scales(law, 0.5, 10.0, 0.0).overdamped);
}

TEST(StabilityLimits, HertzDurationAndOverlapMatchADirectIntegration) {
  ContactLaw law;
  law.model = ContactModel::hertz;
  law.stiffness = 1e5;
  const double m = 0.5, v = 3.0;
  // m delta'' = -k delta^(3/2) from delta = 0 at speed v, until it opens.
  const double dt = 1e-7;
  double delta = 0.0, rate = v, t = 0.0, deepest = 0.0;
  do {
    rate -= 0.5 * dt * law.stiffness * std::pow(std::max(delta, 0.0), 1.5) / m;
    delta += dt * rate;
    rate -= 0.5 * dt * law.stiffness * std::pow(std::max(delta, 0.0), 1.5) / m;
    t += dt;
    deepest = std::max(deepest, delta);
  } while (delta > 0.0);
  const ContactScales s = contact_scales(law, m, v, 0.0);
  EXPECT_NEAR(s.duration / t, 1.0, 5e-3);
  EXPECT_NEAR(s.overlap / deepest, 1.0, 5e-3);
}

}  // namespace
}  // namespace granflow::dem
