// Equilibrium speeds of an elastic gas started at one speed follow the
// Maxwell-Boltzmann distribution, checked by
// a chi-square goodness-of-fit test at significance level 0.001.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "components/velocity.hpp"
#include "systems/edmd/event_driven_gas.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/observables/maxwell_boltzmann.hpp"
#include "tests/systems/edmd/gas_fixture.hpp"

namespace granflow::edmd {
namespace {

template <int D>
void expect_maxwell_boltzmann() {
  constexpr std::size_t particles = 2000;
  constexpr int snapshots = 10, bins = 20;
  World world;
  testing::fill_gas<D>(world, particles, testing::radius_for_packing_fraction<D>(particles, 0.05), true, 5);
  auto& velocity = world.template component<Velocity<D>>();
  std::vector<double> mass(particles, 1.0);
  velocity.values = fixed_speed_velocities<D>(particles, 1.0, 5);
  remove_mean_velocity<D>(velocity.values, mass);

  // T from the energy, which elastic collisions conserve: one fitted
  // parameter, so the test has bins - 2 degrees of freedom.
  double energy = 0.0;
  for (const auto& v : velocity.values) energy += 0.5 * v.squaredNorm();
  const double temperature = 2.0 * energy / (D * particles);
  const double critical = theory::chi_square_critical_0999(bins - 2);

  std::vector<double> initial;
  for (const auto& v : velocity.values) initial.push_back(v.norm());
  // The test must be able to fail: the initial delta distribution is rejected.
  EXPECT_GT(theory::speed_chi_square<D>(initial, temperature, 1.0, bins), critical);

  EventDrivenGas<D> gas(world, CollisionParameters{});
  gas.start(0.0);
  std::vector<double> speeds;
  for (int s = 0; s < snapshots; ++s) {
    // 20 collisions per particle to equilibrate, then 5 between snapshots so
    // that they are nearly independent.
    AdvanceLimits limits;
    limits.max_pair_collisions = static_cast<std::uint64_t>((20 + 5 * s) * particles / 2);
    gas.advance(std::numeric_limits<double>::infinity(), limits);
    gas.synchronize(gas.time());
    for (const auto& v : velocity.values) speeds.push_back(v.norm());
  }
  const double chi2 = theory::speed_chi_square<D>(speeds, temperature, 1.0, bins);
  EXPECT_LT(chi2, critical) << D << "D: chi-square " << chi2 << " for " << speeds.size() << " speeds";

  // Mean and most probable speed against theory (REFERENCE.md).
  double mean = 0.0;
  for (double v : speeds) mean += v;
  mean /= static_cast<double>(speeds.size());
  const double expected_mean = theory::mean_speed<D>(temperature, 1.0);
  // The spread of the speed is ~0.4 of the mean; 20000 samples, of which
  // about a tenth are independent draws, give a standard error below 1 %.
  EXPECT_NEAR(mean / expected_mean, 1.0, 0.015);
}

TEST(MaxwellBoltzmann, EquilibriumSpeeds2D) { expect_maxwell_boltzmann<2>(); }
TEST(MaxwellBoltzmann, EquilibriumSpeeds3D) { expect_maxwell_boltzmann<3>(); }

}  // namespace
}  // namespace granflow::edmd
