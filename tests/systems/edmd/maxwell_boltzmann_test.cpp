// Equilibrium speeds of an elastic gas started at one speed follow the
// Maxwell-Boltzmann distribution (seed 002 eq. 12; REFERENCE.md), checked by
// a chi-square goodness-of-fit test at significance level 0.001.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "components/velocity.hpp"
#include "systems/edmd/event_driven_gas.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "tests/systems/edmd/gas_fixture.hpp"

namespace granflow::edmd {
namespace {

// Cumulative distribution of the speed in units of sqrt(T/m).
template <int D>
double speed_cdf(double x) {
  if constexpr (D == 2)
    return 1.0 - std::exp(-0.5 * x * x);
  else
    return std::erf(x / std::numbers::sqrt2) - std::sqrt(2.0 / std::numbers::pi) * x * std::exp(-0.5 * x * x);
}

// Bin edges (in units of sqrt(T/m)) with equal Maxwell-Boltzmann probability.
template <int D>
std::vector<double> equal_probability_edges(int bins) {
  std::vector<double> edges{0.0};
  for (int k = 1; k < bins; ++k) {
    const double target = static_cast<double>(k) / bins;
    double lo = 0.0, hi = 10.0;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (speed_cdf<D>(mid) < target ? lo : hi) = mid;
    }
    edges.push_back(0.5 * (lo + hi));
  }
  edges.push_back(std::numeric_limits<double>::infinity());
  return edges;
}

// Upper 0.999 quantile of the chi-square distribution with k degrees of
// freedom (Wilson-Hilferty; better than 0.5 % for k >= 10).
double chi_square_critical_0999(int k) {
  const double z = 3.090232;  // standard normal 0.999 quantile
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}

template <int D>
double chi_square(const std::vector<double>& speeds, double temperature, int bins) {
  const auto edges = equal_probability_edges<D>(bins);
  std::vector<double> observed(static_cast<std::size_t>(bins), 0.0);
  for (double v : speeds) {
    const double x = v / std::sqrt(temperature);
    const auto k = std::upper_bound(edges.begin(), edges.end(), x) - edges.begin() - 1;
    observed[static_cast<std::size_t>(k)] += 1.0;
  }
  const double expected = static_cast<double>(speeds.size()) / bins;
  double chi2 = 0.0;
  for (double o : observed) chi2 += (o - expected) * (o - expected) / expected;
  return chi2;
}

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
  const double critical = chi_square_critical_0999(bins - 2);

  std::vector<double> initial;
  for (const auto& v : velocity.values) initial.push_back(v.norm());
  // The test must be able to fail: the initial delta distribution is rejected.
  EXPECT_GT(chi_square<D>(initial, temperature, bins), critical);

  EventDrivenGas<D> gas(world, CollisionParameters{});
  gas.start(0.0);
  std::vector<double> speeds;
  for (int s = 0; s < snapshots; ++s) {
    // 20 collisions per particle to equilibrate, then 5 between snapshots so
    // that they are nearly independent (seed 002 appendix C.2).
    AdvanceLimits limits;
    limits.max_pair_collisions = static_cast<std::uint64_t>((20 + 5 * s) * particles / 2);
    gas.advance(std::numeric_limits<double>::infinity(), limits);
    gas.synchronize(gas.time());
    for (const auto& v : velocity.values) speeds.push_back(v.norm());
  }
  const double chi2 = chi_square<D>(speeds, temperature, bins);
  EXPECT_LT(chi2, critical) << D << "D: chi-square " << chi2 << " for " << speeds.size() << " speeds";

  // Mean and most probable speed against theory (REFERENCE.md).
  double mean = 0.0;
  for (double v : speeds) mean += v;
  mean /= static_cast<double>(speeds.size());
  const double expected_mean = D == 3 ? std::sqrt(8.0 * temperature / std::numbers::pi)
                                      : std::sqrt(std::numbers::pi * temperature / 2.0);
  // The spread of the speed is ~0.4 of the mean; 20000 samples, of which
  // about a tenth are independent draws, give a standard error below 1 %.
  EXPECT_NEAR(mean / expected_mean, 1.0, 0.015);
}

TEST(MaxwellBoltzmann, EquilibriumSpeeds2D) { expect_maxwell_boltzmann<2>(); }
TEST(MaxwellBoltzmann, EquilibriumSpeeds3D) { expect_maxwell_boltzmann<3>(); }

}  // namespace
}  // namespace granflow::edmd
