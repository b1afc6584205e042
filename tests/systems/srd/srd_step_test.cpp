// The SRD step's parts against direct computations: one cell's collision
// conserves momentum and (at restitution 1) energy to round-off, the granular
// rule scales exactly the rotated thermal components by eps_eff^2, counting-
// sort binning equals a brute-force assignment (grid shift and Lees-Edwards
// offset included), the cell reduction equals a plain loop, and the clamp of
// eps_eff <= 0 is counted.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/cell_binning.hpp"
#include "systems/srd/cell_reduction.hpp"
#include "systems/srd/rotation.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {
namespace {

// n particles with random positions in [0, cells) and velocities around `drift`.
template <int D>
World random_fluid(std::array<std::int32_t, D> cells, std::size_t n, std::uint64_t seed, double spread = 1.0) {
  World world(n);
  world.emplace_resource<Clock>();
  auto& x = world.add_component<Position<D>>();
  auto& v = world.add_component<Velocity<D>>();
  for (std::size_t i = 0; i < n; ++i) {
    Philox random(99, seed, 0, i);
    for (int a = 0; a < D; ++a) x[i][a] = random.uniform() * cells[a] * spread;
    for (int a = 0; a < D; ++a) v[i][a] = random.normal() + 0.3 * (a + 1);
  }
  world.emplace_resource<SrdCells<D>>(cells, n);
  return world;
}

template <int D>
void collide(World& world, const RotationParameters& p) {
  auto& cells = world.resource<SrdCells<D>>();
  SrdCellBinning<D>::bin(world.component<Position<D>>(), cells);
  SrdCellReduction<D>::reduce(world, cells);
  SrdRotation<D>(p, 7).run(world);
}

TEST(SrdCell, CollisionConservesMomentumAndEnergyInEveryCell) {
  World world = random_fluid<3>({4, 4, 4}, 640, 1);
  auto& cells = world.resource<SrdCells<3>>();
  SrdCellBinning<3>::bin(world.component<Position<3>>(), cells);
  const auto& v = world.component<Velocity<3>>();
  std::vector<Vec<3>> momentum(cells.cell_count(), Vec<3>::Zero());
  std::vector<double> energy(cells.cell_count(), 0.0);
  for (std::size_t i = 0; i < world.size(); ++i) {
    momentum[cells.cell[i]] += v[i];
    energy[cells.cell[i]] += v[i].squaredNorm();
  }
  RotationParameters p;
  p.angle_degrees = 130.0;
  collide<3>(world, p);
  std::vector<Vec<3>> momentum_after(cells.cell_count(), Vec<3>::Zero());
  std::vector<double> energy_after(cells.cell_count(), 0.0);
  for (std::size_t i = 0; i < world.size(); ++i) {
    momentum_after[cells.cell[i]] += v[i];
    energy_after[cells.cell[i]] += v[i].squaredNorm();
  }
  double worst_momentum = 0, worst_energy = 0, changed = 0;
  for (std::size_t c = 0; c < cells.cell_count(); ++c) {
    worst_momentum = std::max(worst_momentum, (momentum_after[c] - momentum[c]).cwiseAbs().maxCoeff());
    worst_energy = std::max(worst_energy, std::abs(energy_after[c] - energy[c]) / std::max(1.0, energy[c]));
  }
  for (std::size_t i = 0; i < world.size(); ++i) changed += v[i].squaredNorm() > 0;
  EXPECT_LT(worst_momentum, 1e-13);
  EXPECT_LT(worst_energy, 1e-13);
  EXPECT_GT(changed, 600);
}

TEST(SrdCell, GranularRuleScalesTheRotatedThermalPartByEpsEffSquared) {
  // All particles in cell 0: the rotation axis and eps_eff are known.
  World world = random_fluid<3>({2, 2, 2}, 40, 2, 0.5);
  auto& cells = world.resource<SrdCells<3>>();
  SrdCellBinning<3>::bin(world.component<Position<3>>(), cells);
  SrdCellReduction<3>::reduce(world, cells);
  ASSERT_EQ(cells.particles_in(0), 40u);
  RotationParameters p;
  p.angle_degrees = 20.0;
  p.restitution = 0.9;
  p.diameter = 0.2;
  p.dt = 0.1;
  const CellRotation<3> r = cell_rotation<3>(rotation_base<3>(p), 7, 0, 0);
  const Vec<3> axis(r.axis[0], r.axis[1], r.axis[2]);
  const Vec<3> mean = cells.velocity[0];
  bool clamped = false;
  const double eps = effective_restitution(0.9, 0.2, 40.0, cells.theta[0], 0.1, clamped);
  ASSERT_FALSE(clamped);
  ASSERT_LT(eps, 0.999);
  const auto split = [&](const World& w) {
    double along = 0, across = 0;
    for (const auto& u : w.component<Velocity<3>>().values) {
      const Vec<3> t = u - mean;
      along += t.dot(axis) * t.dot(axis);
      across += t.squaredNorm() - t.dot(axis) * t.dot(axis);
    }
    return std::pair{along, across};
  };
  const auto [along0, across0] = split(world);
  SrdRotation<3>(p, 7).run(world);
  const auto [along1, across1] = split(world);
  EXPECT_NEAR(along1, along0, 1e-12 * along0);
  EXPECT_NEAR(across1, eps * eps * across0, 1e-12 * across0);
}

TEST(SrdCell, BinningEqualsABruteForceAssignmentWithShiftAndShear) {
  const std::array<std::int32_t, 3> dims{5, 7, 3};
  World world = random_fluid<3>(dims, 2000, 3);
  auto& cells = world.resource<SrdCells<3>>();
  cells.shift = {0.31, -0.47, 0.12};
  cells.shear = {0.8, 2.35};
  SrdCellBinning<3>::bin(world.component<Position<3>>(), cells);
  const auto& x = world.component<Position<3>>();
  std::map<std::uint32_t, std::vector<std::uint32_t>> members;
  for (std::uint32_t i = 0; i < world.size(); ++i) {
    double s[3] = {x[i][0] + 0.31, x[i][1] - 0.47, x[i][2] + 0.12};
    if (s[1] < 0) {  // below the lower plane: the lower image, displaced by -offset
      s[1] += dims[1];
      s[0] += 2.35;
    } else if (s[1] >= dims[1]) {
      s[1] -= dims[1];
      s[0] -= 2.35;
    }
    std::uint32_t c[3];
    for (int a = 0; a < 3; ++a) {
      const double w = std::fmod(std::fmod(s[a], dims[a]) + dims[a], dims[a]);
      c[a] = static_cast<std::uint32_t>(std::floor(w));
    }
    const std::uint32_t index = (c[2] * dims[1] + c[1]) * dims[0] + c[0];
    ASSERT_EQ(cells.cell[i], index) << "particle " << i;
    members[index].push_back(i);
  }
  for (std::uint32_t c = 0; c < cells.cell_count(); ++c) {
    const std::vector<std::uint32_t> listed(cells.order.begin() + cells.start[c], cells.order.begin() + cells.start[c + 1]);
    EXPECT_EQ(listed, members[c]) << "cell " << c;
  }
}

TEST(SrdCell, ReductionEqualsAPlainLoop) {
  const std::array<std::int32_t, 2> dims{6, 6};
  World world = random_fluid<2>(dims, 900, 4);
  auto& cells = world.resource<SrdCells<2>>();
  cells.shift = {-0.2, 0.4};
  cells.shear = {0.5, 1.7};
  SrdCellBinning<2>::bin(world.component<Position<2>>(), cells);
  SrdCellReduction<2>::reduce(world, cells);
  const auto& x = world.component<Position<2>>();
  const auto& v = world.component<Velocity<2>>();
  std::vector<double> n(cells.cell_count(), 0.0);
  std::vector<Vec<2>> sum(cells.cell_count(), Vec<2>::Zero());
  // Seen from its cell, a particle across the shear plane moves with v_x -+ 0.5.
  const auto seen = [&](std::size_t i) {
    Vec<2> u = v[i];
    const double y = x[i][1] + 0.4;
    if (y >= dims[1]) u[0] -= 0.5;
    if (y < 0) u[0] += 0.5;
    return u;
  };
  for (std::size_t i = 0; i < world.size(); ++i) {
    n[cells.cell[i]] += 1;
    sum[cells.cell[i]] += seen(i);
  }
  std::vector<double> thermal(cells.cell_count(), 0.0);
  for (std::size_t i = 0; i < world.size(); ++i)
    thermal[cells.cell[i]] += (seen(i) - sum[cells.cell[i]] / n[cells.cell[i]]).squaredNorm();
  for (std::size_t c = 0; c < cells.cell_count(); ++c) {
    if (n[c] == 0) continue;
    EXPECT_NEAR(cells.mass[c], n[c], 1e-12);
    EXPECT_LT((cells.velocity[c] - sum[c] / n[c]).norm(), 1e-12);
    EXPECT_NEAR(cells.theta[c], thermal[c] / (2 * n[c]), 1e-12);
  }
}

TEST(SrdCell, NonPositiveEffectiveRestitutionIsClampedAndCounted) {
  World world = random_fluid<2>({4, 4}, 800, 5);
  RotationParameters p;
  p.restitution = 0.0;
  p.diameter = 2.0;  // (1 - 0) 4 x 50 x sqrt(theta) x 1: far below 0
  SrdRotation<2> rotation(p, 7);
  auto& cells = world.resource<SrdCells<2>>();
  SrdCellBinning<2>::bin(world.component<Position<2>>(), cells);
  SrdCellReduction<2>::reduce(world, cells);
  rotation.run(world);
  EXPECT_EQ(cells.clamped_cells, 16u);
  EXPECT_EQ(rotation.total_clamped(), 16u);
  // eps_eff = 0: every particle leaves with its cell's mean velocity.
  SrdCellReduction<2>::reduce(world, cells);
  for (std::size_t c = 0; c < cells.cell_count(); ++c) EXPECT_LT(cells.theta[c], 1e-20);
}

}  // namespace
}  // namespace granflow::srd
