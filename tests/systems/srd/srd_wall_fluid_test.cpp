// An SRD fluid between two walls, driven by the systems directly: with
// specular (slip) walls at rest the total kinetic energy is conserved to
// round-off (rotations and reflections both keep it); between no-slip walls
// at the fluid's temperature, whose ghost particles exchange momentum and
// energy with the cut cells, the fluid stays at that temperature, at rest,
// and with a flat density profile, and walls hotter than the fluid heat it
// to their temperature. Every particle stays between the walls.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "components/clock.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/cell_binning.hpp"
#include "systems/srd/cell_reduction.hpp"
#include "systems/srd/grid_shift.hpp"
#include "systems/srd/rotation.hpp"
#include "systems/srd/streaming.hpp"

namespace granflow::srd {
namespace {

constexpr int per_cell = 10;
constexpr double height = 10.0;

struct FluidOptions {
  double wall_temperature = 1.0;
  bool ghosts = true;
  double floor_amplitude = 0.0, floor_omega = 0.0;
  BodyForce<3> force;
  double restitution = 1.0;
};

struct WalledFluid {
  World world;
  std::vector<std::unique_ptr<System>> steps;

  WalledFluid(WallKind kind, std::uint64_t seed, FluidOptions o = {}) {
    const std::array<std::int32_t, 3> box{8, 8, static_cast<std::int32_t>(height)};
    const std::size_t n = per_cell * 8 * 8 * static_cast<std::size_t>(height);
    world.resize(n);
    world.emplace_resource<Clock>();
    auto& x = world.add_component<Position<3>>();
    auto& v = world.add_component<Velocity<3>>();
    for (std::size_t i = 0; i < n; ++i) {
      Philox random(stream::srd_initial, seed, 0, i);
      for (int a = 0; a < 3; ++a) x[i][a] = random.uniform() * box[a];
      for (int a = 0; a < 3; ++a) v[i][a] = random.normal();
    }
    std::vector<Wall> walls(2);
    for (int k = 0; k < 2; ++k) {
      walls[k].axis = 2;
      walls[k].side = k == 0 ? -1 : +1;
      walls[k].rest = k == 0 ? 0.0 : height;
      walls[k].kind = kind;
      walls[k].temperature = o.wall_temperature;
      walls[k].ghosts = o.ghosts;
    }
    walls[0].amplitude = o.floor_amplitude;
    walls[0].omega = o.floor_omega;
    auto& cells = world.emplace_resource<SrdCells<3>>(box, n, walls);
    cells.ghost_fill = per_cell;
    cells.seed = seed;
    cells.record_energy = true;
    SrdCellBinning<3>::sort(world, cells);
    RotationParameters p;
    p.angle_degrees = 130.0;
    p.restitution = o.restitution;
    p.diameter = 0.3;
    p.dt = 0.5;
    steps.push_back(std::make_unique<SrdStreaming<3>>(0.5, 0.0, o.force));
    steps.push_back(std::make_unique<SrdGridShift<3>>(seed, true));
    steps.push_back(std::make_unique<SrdCellBinning<3>>(10));
    steps.push_back(std::make_unique<SrdCellReduction<3>>());
    steps.push_back(std::make_unique<SrdRotation<3>>(p, seed));
  }
  void advance() {
    for (auto& s : steps) s->run(world);
  }
  const std::vector<Vec<3>>& positions() { return world.component<Position<3>>().values; }
  const std::vector<Vec<3>>& velocities() { return world.component<Velocity<3>>().values; }
  double energy() {
    double sum = 0.0;
    for (const auto& v : velocities()) sum += 0.5 * v.squaredNorm();
    return sum;
  }
  double height_energy(double g) {
    double sum = 0.0;
    for (const auto& x : positions()) sum -= g * x[2];
    return sum;
  }
};

TEST(SrdWallFluid, SlipWallsConserveEnergy) {
  WalledFluid fluid(WallKind::slip, 3);
  const double e0 = fluid.energy();
  for (int step = 0; step < 200; ++step) fluid.advance();
  EXPECT_GT(fluid.world.resource<SrdCells<3>>().wall_reflections, 1000u);
  EXPECT_NEAR(fluid.energy(), e0, 1e-11 * e0);
  for (const auto& x : fluid.positions()) {
    ASSERT_GE(x[2], 0.0);
    ASSERT_LE(x[2], height);
  }
}

TEST(SrdWallFluid, NoSlipWallsAtTheFluidTemperatureKeepItAtRest) {
  WalledFluid fluid(WallKind::no_slip, 4);
  const auto n = static_cast<double>(fluid.world.size());
  double temperature = 0.0, samples = 0.0;
  Vec<3> drift = Vec<3>::Zero();
  std::vector<double> layers(static_cast<std::size_t>(height), 0.0);
  for (int step = 0; step < 400; ++step) {
    fluid.advance();
    if (step < 100) continue;  // the walls' layers settle
    Vec<3> mean = Vec<3>::Zero();
    for (const auto& v : fluid.velocities()) mean += v;
    mean /= n;
    temperature += 2.0 * fluid.energy() / (3.0 * n);
    drift += mean;
    for (const auto& x : fluid.positions()) layers[std::min<std::size_t>(layers.size() - 1, static_cast<std::size_t>(x[2]))] += 1.0;
    samples += 1.0;
  }
  temperature /= samples;
  drift /= samples;
  // One snapshot's temperature has a relative error sqrt(2 / (3 N)) = 1 %,
  // its mean velocity sqrt(kT / N) = 0.0125 per component; the averages over
  // 300 correlated steps are no worse.
  std::printf("temperature %.4f, drift (%.4f %.4f %.4f)\n", temperature, drift[0], drift[1], drift[2]);
  EXPECT_NEAR(temperature, 1.0, 0.03);
  EXPECT_LT(drift.norm(), 0.04);
  // Density: each layer's mean count within 5 % of the mean (a layer holds
  // 640 particles: 4 % per snapshot, averaged over 300).
  const double expected = n / static_cast<double>(layers.size());
  for (std::size_t k = 0; k < layers.size(); ++k)
    EXPECT_NEAR(layers[k] / samples / expected, 1.0, 0.05) << "layer " << k;
  for (const auto& x : fluid.positions()) {
    ASSERT_GE(x[2], 0.0);
    ASSERT_LE(x[2], height);
  }
}

// The ghosts carry the walls' temperature into the fluid: walls at 1.5 heat
// a fluid that starts at 1 (bounce-back alone keeps every particle's energy).
TEST(SrdWallFluid, HotNoSlipWallsHeatTheFluidToTheirTemperature) {
  WalledFluid fluid(WallKind::no_slip, 5, {.wall_temperature = 1.5});
  const auto n = static_cast<double>(fluid.world.size());
  double temperature = 0.0, samples = 0.0;
  for (int step = 0; step < 4000; ++step) {
    fluid.advance();
    if (step < 1000) continue;  // relaxed by then (about 500 steps from 1 to 1.47)
    temperature += 2.0 * fluid.energy() / (3.0 * n);
    samples += 1.0;
  }
  temperature /= samples;
  std::printf("walls at 1.5: temperature %.4f\n", temperature);
  EXPECT_NEAR(temperature, 1.5, 0.045);
}

// The energy balance of a granular fluid shaken from below under gravity:
// what the vibrating floor gives by its reflections, less what the
// collisions take, is the change of kinetic plus potential energy, to
// round-off, step by step; with ghost particles in the cells a no-slip wall
// cuts, their exchange enters the balance as well. Each term is measured
// apart (the state, the reflections, the collisions).
TEST(SrdWallFluid, VibratingFloorEnergyEqualsTheChangeOfEnergyPlusDissipation) {
  struct Case {
    WallKind kind;
    bool ghosts;
  };
  for (const Case c : {Case{WallKind::slip, false}, Case{WallKind::no_slip, false}, Case{WallKind::no_slip, true}}) {
    FluidOptions o;
    o.ghosts = c.ghosts;
    o.floor_amplitude = 0.5;
    o.floor_omega = 2.0;
    o.force.acceleration[2] = -0.2;
    o.restitution = 0.9;
    WalledFluid fluid(c.kind, 6, o);
    auto& cells = fluid.world.resource<SrdCells<3>>();
    const double e0 = fluid.energy() + fluid.height_energy(-0.2);
    double injected = 0.0, dissipated = 0.0, exchanged = 0.0;
    for (int step = 0; step < 300; ++step) {
      fluid.advance();
      injected += cells.step_wall_work;
      dissipated -= cells.step_collision_energy;
      exchanged += cells.step_ghost_cell_energy;
    }
    const double e = fluid.energy() + fluid.height_energy(-0.2);
    std::printf("kind %d ghosts %d: E %.6g -> %.6g, injected %.6g, dissipated %.6g, ghost cells %.6g\n",
                static_cast<int>(c.kind), c.ghosts, e0, e, injected, dissipated, exchanged);
    EXPECT_GT(injected, 0.01 * e0);
    EXPECT_GT(dissipated, 0.01 * e0);
    if (!c.ghosts) {
      EXPECT_EQ(exchanged, 0.0);
    }
    // Round-off: about 1e-16 of E per particle and step, summed in order.
    EXPECT_NEAR(e - e0, injected - dissipated + exchanged, 1e-9 * e0);
  }
}

// A force in a slab accelerates only the particles in it: the momentum the
// fluid gains in a step (collisions keep it, the box is periodic) is g dt
// times the particles in the slab at the step's start.
TEST(SrdWallFluid, SlabForceGivesMomentumOnlyToTheSlabsParticles) {
  World world;
  const std::array<std::int32_t, 3> box{8, 8, 8};
  const std::size_t n = 5000;
  world.resize(n);
  world.emplace_resource<Clock>();
  auto& x = world.add_component<Position<3>>();
  auto& v = world.add_component<Velocity<3>>();
  for (std::size_t i = 0; i < n; ++i) {
    Philox random(stream::srd_initial, 7, 0, i);
    for (int a = 0; a < 3; ++a) x[i][a] = random.uniform() * box[a];
    for (int a = 0; a < 3; ++a) v[i][a] = random.normal();
  }
  world.emplace_resource<SrdCells<3>>(box, n);
  BodyForce<3> force;
  force.acceleration[0] = 0.25;
  force.slab_axis = 1;
  force.from = 2.0;
  force.to = 5.0;
  SrdStreaming<3> streaming(0.5, 0.0, force);
  for (int step = 0; step < 20; ++step) {
    double in_slab = 0.0, before = 0.0, after = 0.0;
    std::vector<double> vx(n);
    for (std::size_t i = 0; i < n; ++i) {
      in_slab += force.acts_at(x[i].data()) ? 1.0 : 0.0;
      before += v[i][0];
      vx[i] = v[i][0];
    }
    const std::vector<Vec<3>> start = x.values;
    streaming.run(world);
    for (std::size_t i = 0; i < n; ++i) {
      after += v[i][0];
      ASSERT_NEAR(v[i][0] - vx[i], force.acts_at(start[i].data()) ? 0.125 : 0.0, 1e-14) << "particle " << i;
    }
    EXPECT_GT(in_slab, 1000.0);
    EXPECT_NEAR(after - before, 0.125 * in_slab, 1e-9);
  }
}

}  // namespace
}  // namespace granflow::srd
