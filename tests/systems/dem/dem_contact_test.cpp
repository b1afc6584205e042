// Soft-sphere contacts against the linear spring-dashpot theory: two spheres
// head-on (and a sphere on a wall) leave with the restitution e and after
// the contact time t_c of the formulas in systems/dem/contact_law.hpp,
// within 1 %, for e = 0.3, 0.7, 0.95 and mass ratios 1 and 3 (dt = t_c/500:
// the velocity Verlet error of a contact is O(dt^2) ~ 1e-5; start and end
// are found by linear interpolation of the overlap, O(dt^2) too). At e = 1
// a gas of spheres in a walled box keeps its energy within a bound over
// 1e5 steps, and for compressed contacts that never open the bound falls
// as dt^2 (halving dt quarters it, within 20 %). Neighbour lists never miss
// a contact an all-pairs search finds; a settled bed stays at rest and the
// floor carries its weight; the same run on 1 and 2 threads is identical
// (with friction and reordering); a sphere on an incline rolls or slides as
// Coulomb friction says.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "components/angular_velocity.hpp"
#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/dem/contact_forces.hpp"
#include "systems/dem/dem_energy.hpp"
#include "systems/dem/dem_watchdog.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/position_verlet.hpp"
#include "systems/dem/velocity_verlet.hpp"

namespace granflow::dem {
namespace {

struct Spheres {
  World world;
  std::vector<std::unique_ptr<System>> steps;
  double dt;

  Spheres(std::size_t n, std::array<double, 3> box, std::array<bool, 3> periodic, double dt_, double skin = 0.2)
      : dt(dt_) {
    world.resize(n);
    world.emplace_resource<Clock>();
    world.add_component<Position<3>>();
    world.add_component<Velocity<3>>();
    world.add_component<Force<3>>();
    world.add_component<Radius>();
    world.add_component<Mass>();
    auto& b = world.emplace_resource<Box<3>>();
    b.length = box;
    b.periodic = periodic;
    world.emplace_resource<NeighbourList<3>>().skin = skin;
    world.emplace_resource<DemInteractions<3>>();
    world.emplace_resource<DemLedger>();
    // No bounds for the watchdog: these tests hold the spheres themselves.
    world.emplace_resource<RunControl>();
    auto& watch = world.emplace_resource<DemWatch<3>>();
    watch.lower.fill(-std::numeric_limits<double>::infinity());
    watch.upper.fill(std::numeric_limits<double>::infinity());
  }
  DemInteractions<3>& interactions() { return world.resource<DemInteractions<3>>(); }
  // Coulomb friction mu with the default tangential spring and dashpot: the
  // spheres rotate, and the lists keep each contact's spring.
  void enable_friction(double mu) {
    for (auto& w : world.add_component<AngularVelocity>().values) w.setZero();
    for (auto& t : world.add_component<Torque>().values) t.setZero();
    interactions().friction.mu = mu;
    interactions().friction.dt = dt;
    auto& nl = world.resource<NeighbourList<3>>();
    nl.keeps_history = true;
    nl.walls = interactions().walls.size();
  }
  Vec<3>& x(std::size_t i) { return world.component<Position<3>>()[i]; }
  Vec<3>& v(std::size_t i) { return world.component<Velocity<3>>()[i]; }
  void set(std::size_t i, Vec<3> position, Vec<3> velocity, double radius, double mass) {
    x(i) = position;
    v(i) = velocity;
    world.component<Radius>()[i] = radius;
    world.component<Mass>()[i] = mass;
  }
  // Forces at the start, then the step chain (velocity or position Verlet).
  void start(bool position_verlet = false) {
    DemNeighbourList<3>().run(world);
    DemContactForces<3>().run(world);
    if (position_verlet) {
      DemPositionVerlet<3>::start(world, dt);
      steps.push_back(std::make_unique<DemPositionVerlet<3>>(dt));
      steps.push_back(std::make_unique<DemNeighbourList<3>>());
      steps.push_back(std::make_unique<DemContactForces<3>>());
      return;
    }
    steps.push_back(std::make_unique<DemKickDrift<3>>(dt));
    steps.push_back(std::make_unique<DemNeighbourList<3>>());
    steps.push_back(std::make_unique<DemContactForces<3>>());
    steps.push_back(std::make_unique<DemKick<3>>(dt));
    steps.push_back(std::make_unique<DemEnergyAccount<3>>(dt));
  }
  void advance() {
    for (auto& s : steps) s->run(world);
  }
  double energy() {
    double e = interactions().elastic;
    for (std::size_t i = 0; i < world.size(); ++i) {
      e += 0.5 * world.component<Mass>()[i] * v(i).squaredNorm();
      for (int a = 0; a < 3; ++a) e -= world.component<Mass>()[i] * interactions().gravity[a] * x(i)[a];
    }
    return e;
  }
};

struct Collision {
  double restitution, duration;
};

// Two spheres approaching along x at relative speed 1, or (wall) one sphere
// falling onto a resting floor at speed 1, without gravity.
Collision collide(double e, double mass_ratio, bool wall, bool position_verlet = false) {
  ContactLaw law;
  law.stiffness = 1e4;
  law.damping = ContactLaw::lsd_damping_factor(e);
  const double m1 = 1.0, m2 = mass_ratio;
  const double m_eff = wall ? m1 : m1 * m2 / (m1 + m2);
  const double t_c = law.contact_time(m_eff);
  Spheres s(wall ? 1 : 2, {10, 10, 10}, {false, false, false}, t_c / 500);
  if (wall) {
    s.set(0, {5, 5, 0.52}, {0, 0, -1}, 0.5, m1);
    DemWall floor;
    floor.axis = 2;
    floor.side = -1;
    floor.law = law;
    s.interactions().walls.push_back(floor);
  } else {
    s.set(0, {4.48, 5, 5}, {m2 / (m1 + m2), 0, 0}, 0.5, m1);
    s.set(1, {5.52, 5, 5}, {-m1 / (m1 + m2), 0, 0}, 0.5, m2);
  }
  s.interactions().law = law;
  s.start(position_verlet);
  const auto overlap = [&] { return wall ? 0.5 - s.x(0)[2] : 1.0 - (s.x(1)[0] - s.x(0)[0]); };
  double begin = -1, end = -1, previous = overlap();
  for (int step = 1; step < 100000 && end < 0; ++step) {
    s.advance();
    const double now = overlap(), t = step * s.dt;
    if (begin < 0 && previous <= 0 && now > 0) begin = t - s.dt * now / (now - previous);
    if (begin >= 0 && previous > 0 && now <= 0) end = t - s.dt * now / (now - previous);
    previous = now;
  }
  const double after = wall ? s.v(0)[2] : s.v(1)[0] - s.v(0)[0];
  return {after, end - begin};
}

// Position Verlet, whose dampers see the backward-difference velocity
// (x(t) - x(t - dt)) / dt: the same restitution and contact time within 1 %
// at dt = t_c / 500. (Velocity Verlet's dampers see its half-step velocity,
// which is the same difference, so the two move the spheres alike; they
// differ in the velocity they report.)
TEST(DemContact, PositionVerletGivesTheSameCollision) {
  for (const double e : {0.3, 0.7, 0.95}) {
    ContactLaw law;
    law.stiffness = 1e4;
    law.damping = ContactLaw::lsd_damping_factor(e);
    const auto c = collide(e, 1.0, false, true);
    std::printf("position Verlet, e = %.2f: restitution %.5f, contact time %.6f (theory %.6f)\n", e, c.restitution,
                c.duration, law.contact_time(0.5));
    EXPECT_NEAR(c.restitution, e, 0.01 * e);
    EXPECT_NEAR(c.duration, law.contact_time(0.5), 0.01 * law.contact_time(0.5));
  }
}

TEST(DemContact, HeadOnRestitutionAndContactTimeMatchTheSpringDashpot) {
  for (const bool wall : {false, true})
    for (const double e : {0.3, 0.7, 0.95})
      for (const double ratio : {1.0, 3.0}) {
        if (wall && ratio != 1.0) continue;
        ContactLaw law;
        law.stiffness = 1e4;
        law.damping = ContactLaw::lsd_damping_factor(e);
        const double m_eff = wall ? 1.0 : ratio / (1.0 + ratio);
        const auto c = collide(e, ratio, wall);
        std::printf("%s e = %.2f ratio %.0f: restitution %.5f, contact time %.6f (theory %.6f)\n", wall ? "wall" : "pair", e,
                    ratio, c.restitution, c.duration, law.contact_time(m_eff));
        EXPECT_NEAR(c.restitution, e, 0.01 * e);
        EXPECT_NEAR(c.duration, law.contact_time(m_eff), 0.01 * law.contact_time(m_eff));
      }
}

// Elastic spheres on a cubic lattice in a walled box: `spacing` below the
// diameter compresses every contact (contacts then never open and the
// motion is smooth), above it the spheres form a gas of binary collisions.
double energy_error(double dt, int steps, double spacing, double speed) {
  ContactLaw law;
  law.stiffness = 1e4;
  const double side = 5 * spacing + (spacing < 1.0 ? -0.01 : 0.6);
  Spheres s(125, {side, side, side}, {false, false, false}, dt);
  int i = 0;
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 5; ++b)
      for (int c = 0; c < 5; ++c, ++i) {
        Philox random(1, 2, 3, static_cast<std::uint64_t>(i));
        const double o = 0.5 * (side - 4 * spacing);
        s.set(static_cast<std::size_t>(i), {o + spacing * a, o + spacing * b, o + spacing * c},
              {speed * random.normal(), speed * random.normal(), speed * random.normal()}, 0.5, 1.0);
      }
  s.interactions().law = law;
  for (int axis = 0; axis < 3; ++axis)
    for (int side_sign : {-1, 1}) {
      DemWall w;
      w.axis = axis;
      w.side = side_sign;
      w.rest = side_sign < 0 ? 0.0 : side;
      w.law = law;
      s.interactions().walls.push_back(w);
    }
  s.start();
  const double e0 = s.energy();
  double worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    s.advance();
    worst = std::max(worst, std::abs(s.energy() - e0));
  }
  return worst / e0;
}

// Compressed contacts that never open: the velocity Verlet energy error is
// bounded (no drift over 1e5 steps) and scales as dt^2. A gas, whose
// contacts open and close between steps, stays within 1 % over 1e5 steps;
// its error is set by the worst of many collisions (each one's error falls
// as dt^3: one contact's onset between two steps), too irregular to scale.
TEST(DemContact, ElasticEnergyErrorIsBoundedAndFallsAsDtSquared) {
  // A contact's period is 2 t_c = 2 pi / sqrt(2 k) = 0.044: dt = 1/40 and 1/80 of it.
  const double coarse = energy_error(1.1e-3, 100000, 0.98, 0.05), fine = energy_error(0.55e-3, 200000, 0.98, 0.05);
  std::printf("compressed lattice, largest relative energy error: dt = 1.1e-3 %.4g, 0.55e-3 %.4g, ratio %.3f\n", coarse,
              fine, coarse / fine);
  EXPECT_LT(coarse, 1e-3);
  EXPECT_NEAR(coarse / fine, 4.0, 0.8);
  const double gas = energy_error(1.1e-3, 100000, 1.6, 1.0);
  std::printf("gas of binary collisions: %.4g\n", gas);
  EXPECT_LT(gas, 1e-2);
}

TEST(DemContact, NeighbourListsFindEveryContactAllPairsFinds) {
  // In index order, and with the spheres put in cell order at every build.
  for (const bool reorder : {false, true}) {
    Spheres s(400, {10, 10, 10}, {true, true, false}, 1e-3, 0.1);
    for (std::size_t i = 0; i < 400; ++i) {
      Philox random(4, 5, 6, i);
      s.set(i, {10 * random.uniform(), 10 * random.uniform(), 0.5 + 9 * random.uniform()},
            {3 * random.normal(), 3 * random.normal(), 3 * random.normal()}, 0.3 + 0.2 * random.uniform(), 1.0);
    }
    ContactLaw law;
    law.stiffness = 1e3;
    s.interactions().law = law;
    s.world.resource<NeighbourList<3>>().reorder = reorder;
    s.start();
    const auto& box = s.world.resource<Box<3>>();
    const auto& radius = s.world.component<Radius>();
    for (int step = 0; step < 2000; ++step) {
      s.advance();
      if (step % 50) continue;
      const auto& nl = s.world.resource<NeighbourList<3>>();
      for (std::size_t i = 0; i < 400; ++i)
        for (std::size_t j = 0; j < 400; ++j) {
          if (i == j) continue;
          double d[3];
          box.separation(s.x(i), s.x(j), d);
          const double reach = radius[i] + radius[j];
          if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= reach * reach) continue;
          // Half lists: the pair is listed once, under the one of the two that comes first in cell order.
          int listed = 0;
          for (auto [q, end] = nl.pairs_of(i); q < end; ++q) listed += nl.list[q] == j;
          for (auto [q, end] = nl.pairs_of(j); q < end; ++q) listed += nl.list[q] == i;
          ASSERT_EQ(listed, 1) << "reorder " << reorder << ", step " << step << ": contact " << i << "-" << j
                               << " listed " << listed << " times";
        }
    }
    EXPECT_GT(s.world.resource<NeighbourList<3>>().builds, 5u);
  }
}

// A bed poured onto a floor (periodic sideways) comes to rest and stays at
// rest: over 1e5 steps after settling its kinetic energy stays below 1e-8
// of N m g d and ends below where it started (dying out, no creep), and the
// floor carries its weight: the mean normal force on it equals N m g within
// 1 %.
TEST(DemContact, SettledBedRestsAndTheFloorCarriesItsWeight) {
  ContactLaw law;
  law.stiffness = 2e4;
  law.damping = ContactLaw::lsd_damping_factor(0.3);
  const double dt = law.contact_time(0.5) / 50;
  Spheres s(400, {8, 8, 40}, {true, true, false}, dt);
  for (std::size_t i = 0; i < 400; ++i) {
    Philox random(10, 11, 12, i);
    const std::size_t layer = i / 49, k = i % 49;
    // A loose lattice, jittered so that the bed does not crystallise in columns.
    s.set(i, {0.6 + 1.1 * (k % 7) + 0.05 * random.uniform(), 0.6 + 1.1 * (k / 7) + 0.05 * random.uniform(), 1.0 + 1.2 * layer},
          {0.1 * random.normal(), 0.1 * random.normal(), 0.1 * random.normal()}, 0.5, 1.0);
  }
  // No net sideways drift: a frictionless floor could never stop it.
  Vec<3> mean = Vec<3>::Zero();
  for (std::size_t i = 0; i < 400; ++i) mean += s.v(i) / 400.0;
  for (std::size_t i = 0; i < 400; ++i) s.v(i) -= mean;
  s.interactions().law = law;
  s.interactions().gravity = {0, 0, -1};
  DemWall floor;
  floor.law = law;
  s.interactions().walls.push_back(floor);
  s.start();
  const auto kinetic = [&] {
    double e = 0.0;
    for (std::size_t i = 0; i < 400; ++i) e += 0.5 * s.v(i).squaredNorm();
    return e;
  };
  for (int k = 0; k < static_cast<int>(160.0 / dt); ++k) s.advance();  // 160 time units to settle
  double worst = 0.0, floor_force = 0.0;
  const double first = kinetic();
  constexpr int steps = 100000;
  for (int k = 0; k < steps; ++k) {
    s.advance();
    worst = std::max(worst, kinetic());
    floor_force += s.interactions().wall_force[0];
  }
  floor_force /= steps;
  std::printf("settled bed: kinetic energy %.3g at the start of the window, %.3g at its end, %.3g at most "
              "(N m g d = 400); mean floor force %.6g (weight 400)\n", first, kinetic(), worst, floor_force);
  EXPECT_LT(worst, 1e-8 * 400);
  EXPECT_LE(kinetic(), first);  // dying out, not creeping
  EXPECT_NEAR(floor_force, 400.0, 4.0);
}

TEST(DemContact, SameResultOnOneAndTwoThreads) {
  const auto run = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    Spheres s(3000, {12, 12, 30}, {true, true, false}, 2e-4);
    for (std::size_t i = 0; i < 3000; ++i) {
      Philox random(7, 8, 9, i);
      s.set(i, {12 * random.uniform(), 12 * random.uniform(), 0.5 + 29 * random.uniform()},
            {random.normal(), random.normal(), random.normal()}, 0.4, 1.0);
    }
    ContactLaw law;
    law.stiffness = 1e4;
    law.damping = ContactLaw::lsd_damping_factor(0.8);
    s.interactions().law = law;
    s.interactions().gravity = {0, 0, -1};
    DemWall floor;
    floor.law = law;
    floor.amplitude = 0.1;
    floor.omega = 30;
    s.interactions().walls.push_back(floor);
    // Friction, rotation and reordering at the rebuilds take part too.
    s.enable_friction(0.5);
    s.world.resource<NeighbourList<3>>().reorder = true;
    s.start();
    for (int k = 0; k < 500; ++k) s.advance();
    auto values = s.world.component<Velocity<3>>().values;
    for (const auto& w : s.world.component<AngularVelocity>().values) values.push_back(w);
    return values;
  };
  const auto one = run(1), two = run(2);
  for (std::size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], two[i]) << "sphere " << i;
}

// A sphere on an inclined plane (gravity tilted by theta against the floor's
// normal) with Coulomb friction mu: below tan theta = (7/2) mu it rolls
// without slipping, accelerating at (5/7) g sin theta with its contact
// point at rest; above, it slides at g (sin theta - mu cos theta) while its
// spin grows at (5/2) mu g cos theta / r. The acceleration is the slope of a
// fit to v(t) over 2 time units after the start-up transient has died out
// (the tangential spring's period is ~0.1); 1 % covers the spring's
// residual oscillation and the normal overlap's effect on the lever arm
// (delta / r ~ 1e-4).
TEST(DemContact, SphereOnAnInclineRollsBelowTheFrictionLimitAndSlidesAbove) {
  const double mu = 0.2, g = 1.0, radius = 0.5;
  for (const double tangent : {0.5 * 3.5 * mu, 2.0 * 3.5 * mu}) {
    const double theta = std::atan(tangent);
    ContactLaw law;
    law.stiffness = 1e4;
    law.damping = ContactLaw::lsd_damping_factor(0.5);
    Spheres s(1, {1000, 10, 10}, {false, false, false}, law.contact_time(1.0) / 50);
    const double rest = radius - g * std::cos(theta) / law.stiffness;
    s.set(0, {1, 5, rest}, {0, 0, 0}, radius, 1.0);
    s.interactions().law = law;
    s.interactions().gravity = {g * std::sin(theta), 0, -g * std::cos(theta)};
    DemWall floor;
    floor.law = law;
    s.interactions().walls.push_back(floor);
    s.enable_friction(mu);
    s.start();
    double st = 0, sv = 0, stt = 0, stv = 0, count = 0, slip = 0;
    const int steps = static_cast<int>(3.0 / s.dt);
    for (int k = 1; k <= steps; ++k) {
      s.advance();
      const double t = k * s.dt;
      if (t < 1.0) continue;
      const double v = s.v(0)[0];
      st += t;
      sv += v;
      stt += t * t;
      stv += t * v;
      count += 1;
      // The contact point's velocity: v_x - r w_y (the point sits at -r z).
      slip = std::max(slip, std::abs(v - radius * s.world.component<AngularVelocity>()[0][1]));
    }
    const double a = (count * stv - st * sv) / (count * stt - st * st);
    const bool rolls = tangent < 3.5 * mu;
    const double expected = rolls ? 5.0 / 7.0 * g * std::sin(theta) : g * (std::sin(theta) - mu * std::cos(theta));
    std::printf("incline tan theta = %.2f (limit %.2f): a = %.6f, expected %.6f (%s); largest contact-point speed %.3g\n",
                tangent, 3.5 * mu, a, expected, rolls ? "rolling" : "sliding", slip);
    EXPECT_NEAR(a, expected, 0.01 * expected);
    if (rolls) EXPECT_LT(slip, 1e-3 * a * 3.0);  // at rest against a speed of ~a t
    else EXPECT_GT(slip, 0.1 * a);
  }
}

}  // namespace
}  // namespace granflow::dem
