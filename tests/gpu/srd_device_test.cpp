// The SRD step on the CUDA device against the CPU systems, from the same
// state and seed (label gpu; skips, saying why, where no device is usable).
//
// Tolerances. Both back ends sum each cell's particles in storage order
// about the same first particle, keep the particles in the same order (cell
// order at the same reorderings), draw the same shifts and axes (Philox by
// stream, seed, step, cell) and round multiplies and adds apart (the device
// file is built with --fmad=false); what may differ is the last bit of a
// library function (the normal deviates of the ghost particles: log, cos)
// and the order of the device's global sums (thermostat, energy ledger).
// One step: every coordinate within 1e-12 (relative to the thermal speed
// and the box), far above those ulps and far below any real fault (a wrong
// cell or axis changes a velocity by O(1)). 100 steps: 1e-9, round-off
// grows as it is carried through the collisions. Per-cell momentum on the
// device: 1e-12 of the thermal speed. Energy at eps = 1 over 200 steps:
// 1e-10 relative. The granular temperature of a cooling fluid on both, with
// different seeds, over 1000 steps: within 3 % (the run-to-run spread of a
// 40 960-particle fluid is below 1 %).

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/cell_binning.hpp"
#include "systems/srd/cell_reduction.hpp"
#include "systems/srd/grid_shift.hpp"
#include "systems/srd/rotation.hpp"
#include "systems/srd/srd_device.hpp"
#include "systems/srd/srd_device_step.hpp"
#include "systems/srd/streaming.hpp"
#include "systems/srd/thermostat.hpp"

namespace granflow::srd {
namespace {

std::string no_device() {
  const std::string why = device::srd_device_unavailable();
  return why.empty() ? "" : why + ": GPU check skipped";
}

struct Case {
  std::array<std::int32_t, 3> box{16, 16, 16};
  int per_cell = 10;
  double dt = 0.5;
  double angle = 130.0;
  double restitution = 1.0;
  double diameter = 0.3;
  double shear_rate = 0.0;
  double thermostat = 0.0;
  bool walls = false;        // no-slip floor (moving) and ceiling across z, with ghosts
  double gravity = 0.0;      // along -z
  bool record_energy = false;
  std::uint64_t seed = 11;
  std::uint64_t reorder = 7;
};

// One fluid, on the CPU systems or on the device.
struct Fluid {
  World world;
  std::vector<std::unique_ptr<System>> steps;

  Fluid(const Case& c, bool device) {
    const std::size_t n = static_cast<std::size_t>(c.per_cell) * c.box[0] * c.box[1] * c.box[2];
    world.resize(n);
    world.emplace_resource<Clock>();
    auto& x = world.add_component<Position<3>>();
    auto& v = world.add_component<Velocity<3>>();
    for (std::size_t i = 0; i < n; ++i) {
      Philox random(stream::srd_initial, c.seed, 0, i);
      for (int a = 0; a < 3; ++a) x[i][a] = random.uniform() * c.box[a];
      for (int a = 0; a < 3; ++a) v[i][a] = random.normal();
      if (c.shear_rate > 0) v[i][0] += c.shear_rate * (x[i][1] - 0.5 * c.box[1]);
    }
    std::vector<Wall> walls;
    if (c.walls) {
      walls.resize(2);
      for (int k = 0; k < 2; ++k) {
        walls[k].axis = 2;
        walls[k].side = k == 0 ? -1 : 1;
        walls[k].rest = k == 0 ? 0.0 : c.box[2];
        walls[k].temperature = 1.0;
      }
      walls[0].amplitude = 0.5;
      walls[0].omega = 0.7;
    }
    SrdCells<3> unshifted(c.box, n);
    SrdCellBinning<3>::sort(world, unshifted);
    auto& cells = world.emplace_resource<SrdCells<3>>(c.box, n, walls);
    cells.ghost_fill = c.per_cell;
    cells.seed = c.seed;
    cells.record_moments = c.shear_rate > 0;
    cells.record_energy = c.record_energy;
    SrdStreaming<3>::set_shear(cells, c.shear_rate, 0.0);
    BodyForce<3> force;
    force.acceleration[2] = -c.gravity;
    RotationParameters p;
    p.angle_degrees = c.angle;
    p.restitution = c.restitution;
    p.diameter = c.diameter;
    p.dt = c.dt;
    p.record_transfer = c.shear_rate > 0;
    if (device) {
      DeviceStepParameters d;
      d.dt = c.dt;
      d.shear_rate = c.shear_rate;
      d.force = force;
      d.rotation = p;
      d.seed = c.seed;
      d.reorder_interval = c.reorder;
      d.thermostat = c.thermostat;
      d.thermostat_removes_drift = !c.walls;
      steps.push_back(std::make_unique<SrdDeviceStep<3>>(d, cells, n));
    } else {
      steps.push_back(std::make_unique<SrdStreaming<3>>(c.dt, c.shear_rate, force));
      steps.push_back(std::make_unique<SrdGridShift<3>>(c.seed, true));
      steps.push_back(std::make_unique<SrdCellBinning<3>>(c.reorder));
      steps.push_back(std::make_unique<SrdCellReduction<3>>());
      steps.push_back(std::make_unique<SrdRotation<3>>(p, c.seed));
      if (c.thermostat > 0) steps.push_back(std::make_unique<SrdThermostat<3>>(c.thermostat, !c.walls));
    }
  }
  void advance(int count) {
    for (int k = 0; k < count; ++k)
      for (auto& s : steps) s->run(world);
    for (auto& s : steps) s->synchronise_host(world);
  }
  const std::vector<Vec<3>>& x() const { return world.component<Position<3>>().values; }
  const std::vector<Vec<3>>& v() const { return world.component<Velocity<3>>().values; }
  const SrdCells<3>& cells() const { return world.resource<SrdCells<3>>(); }
  double energy() const {
    double e = 0.0;
    for (const auto& u : v()) e += 0.5 * u.squaredNorm();
    return e;
  }
};

void expect_same_particles(const Fluid& cpu, const Fluid& gpu, double tolerance, const std::string& what) {
  ASSERT_EQ(cpu.x().size(), gpu.x().size());
  double worst_x = 0.0, worst_v = 0.0;
  for (std::size_t i = 0; i < cpu.x().size(); ++i) {
    worst_x = std::max(worst_x, (cpu.x()[i] - gpu.x()[i]).cwiseAbs().maxCoeff());
    worst_v = std::max(worst_v, (cpu.v()[i] - gpu.v()[i]).cwiseAbs().maxCoeff());
  }
  std::printf("%s: largest difference of x %.3g, of v %.3g\n", what.c_str(), worst_x, worst_v);
  EXPECT_LT(worst_x, tolerance * 16.0) << what;  // the box is 16 cells
  EXPECT_LT(worst_v, tolerance) << what;
  for (std::size_t i = 0; i < cpu.x().size(); ++i) ASSERT_EQ(cpu.cells().cell[i], gpu.cells().cell[i]) << what << ", particle " << i;
}

void compare(const Case& c, const std::string& what) {
  Fluid cpu(c, false), gpu(c, true);
  cpu.advance(1);
  gpu.advance(1);
  expect_same_particles(cpu, gpu, 1e-12, what + ", 1 step");
  for (std::size_t k = 0; k < cpu.cells().cell_count(); ++k) {
    ASSERT_EQ(cpu.cells().count[k], gpu.cells().count[k]) << what << ", cell " << k;
    ASSERT_NEAR(cpu.cells().theta[k], gpu.cells().theta[k], 1e-12) << what << ", cell " << k;
    if (c.shear_rate > 0) {
      ASSERT_NEAR(cpu.cells().transfer[k], gpu.cells().transfer[k], 1e-11) << what << ", cell " << k;
    }
  }
  if (c.record_energy) {
    EXPECT_NEAR(cpu.cells().step_collision_energy, gpu.cells().step_collision_energy, 1e-9 * cpu.energy()) << what;
    EXPECT_NEAR(cpu.cells().step_wall_work, gpu.cells().step_wall_work, 1e-9 * cpu.energy()) << what;
  }
  cpu.advance(99);
  gpu.advance(99);
  expect_same_particles(cpu, gpu, 1e-9, what + ", 100 steps");
  EXPECT_EQ(cpu.cells().wall_reflections, gpu.cells().wall_reflections) << what;
}

TEST(SrdDevice, PeriodicStepAgreesWithTheCpu) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  compare(Case{}, "standard SRD");
  Case granular;
  granular.restitution = 0.9;
  compare(granular, "granular SRD");
}

TEST(SrdDevice, ShearedStepWithThermostatAgreesWithTheCpu) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  Case c;
  c.shear_rate = 0.05;
  c.thermostat = 1.0;
  c.dt = 1.0;
  c.angle = 120.0;
  compare(c, "Lees-Edwards with thermostat");
}

TEST(SrdDevice, WalledStepUnderGravityAgreesWithTheCpu) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  Case c;
  c.walls = true;
  c.gravity = 0.05;
  c.restitution = 0.9;
  c.record_energy = true;
  compare(c, "walls, ghosts, moving floor, gravity");
}

// Each cell's momentum after the collision, from the device's own
// velocities: the mean of its particles equals the cell's mean velocity,
// which the collision must keep (granular too).
TEST(SrdDevice, CollisionKeepsEachCellsMomentum) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  Case c;
  c.restitution = 0.8;
  Fluid gpu(c, true);
  gpu.advance(3);
  const auto& cells = gpu.cells();
  std::vector<Vec<3>> sum(cells.cell_count(), Vec<3>::Zero());
  for (std::size_t i = 0; i < gpu.v().size(); ++i) sum[cells.cell[i]] += gpu.v()[i];
  int checked = 0;
  for (std::size_t k = 0; k < cells.cell_count(); ++k) {
    if (cells.count[k] == 0) continue;
    const Vec<3> mean = sum[k] / static_cast<double>(cells.count[k]);
    ASSERT_LT((mean - cells.velocity[k]).cwiseAbs().maxCoeff(), 1e-12) << "cell " << k;
    ++checked;
  }
  EXPECT_GT(checked, 3000);
}

TEST(SrdDevice, StandardSrdKeepsTheEnergy) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  Fluid gpu(Case{}, true);
  const double e0 = gpu.energy();
  gpu.advance(200);
  EXPECT_NEAR(gpu.energy(), e0, 1e-10 * e0);
}

// Statistics, not bits: a granular fluid cooling on the device and on the
// CPU from different seeds has the same temperature history.
TEST(SrdDevice, CoolingStatisticsAgreeWithTheCpu) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  Case c;
  c.restitution = 0.9;
  c.diameter = 0.3;
  c.dt = 0.1;
  c.angle = 90;
  Case other = c;
  other.seed = 12;
  Fluid cpu(c, false), gpu(other, true);
  const double t0 = cpu.energy();
  for (int block = 0; block < 10; ++block) {
    cpu.advance(100);
    gpu.advance(100);
    std::printf("step %d: E/E0 cpu %.5f gpu %.5f\n", 100 * (block + 1), cpu.energy() / t0, gpu.energy() / t0);
    EXPECT_NEAR(gpu.energy() / cpu.energy(), 1.0, 0.03) << "after " << 100 * (block + 1) << " steps";
  }
  EXPECT_LT(cpu.energy(), 0.5 * t0);  // it did cool
}

}  // namespace
}  // namespace granflow::srd
