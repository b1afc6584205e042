// Self-diffusion of the event-driven gas. Molecular gas: the long-time MSD
// slope lies between 6 D0 (Enskog) and 1.10 x 6 D0 (Enskog misses correlated
// collisions, the velocity autocorrelation's long-time tail of Alder &
// Wainwright 1970: +6.4 +- 1.4 % measured with an established code at N = 1372),
// and the time average equals the ensemble average (ergodic): to 5 %, the
// largest difference up to lag 10 over base seeds 1-6 being 1.4-3.4 %
// (time average below; 4 runs x 1000 particles, MSD(10) known to ~1 %). Granular gas
// (xi = 0.8): ballistic at first, then logarithmic growth, and the time
// average falls far below the ensemble MSD (not ergodic). Runs in parallel
// give the same result on any thread count.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>

#include "scenarios/brownian_edmd.hpp"
#include "tests/scenario_schema.hpp"

namespace granflow::scenarios {
namespace {

Config gas(double restitution, double t_stop) {
  Config config(scenario_schema("brownian_edmd"));
  config.set("collision.restitution", restitution);
  config.set("collision.contact_time", 1e-6);
  config.set("run.t_stop", t_stop);
  config.set("msd.time_average_particles", std::int64_t{1000});
  return config;
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  const auto k = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), at) - x.begin());
  if (k == 0) return y.front();
  if (k == x.size()) return y.back();
  return y[k - 1] + (y[k] - y[k - 1]) * (at - x[k - 1]) / (x[k] - x[k - 1]);
}

TEST(BrownianEdmd, MolecularGasDiffusesSlightlyFasterThanEnskog) {
  const auto r = measure_edmd_msd(gas(1.0, 100.0));
  const double enskog = 6.0 * r.enskog.diffusivity0;
  std::printf("long-time slope %.4f = %.4f x 6 D0\n", r.long_time_slope, r.long_time_slope / enskog);
  EXPECT_GT(r.long_time_slope, enskog);
  EXPECT_LT(r.long_time_slope, 1.10 * enskog);
  // Ballistic start: 3 (T0/m) t^2.
  EXPECT_NEAR(r.msd.front() / (3.0 * r.temperature0 * r.time.front() * r.time.front()), 1.0, 0.02);
  for (std::size_t k = 0; k < r.lag.size(); ++k) {
    if (r.lag[k] > 10.0) break;
    EXPECT_NEAR(r.time_averaged_msd[k] / interpolate(r.time, r.msd, r.lag[k]), 1.0, 0.05) << "lag " << r.lag[k];
  }
}

TEST(BrownianEdmd, GranularGasCrossesOverFromBallisticToLogarithmic) {
  const auto r = measure_edmd_msd(gas(0.8, 50.0));
  const auto local_slope = [&](std::size_t k) {
    return std::log(r.msd[k + 1] / r.msd[k]) / std::log(r.time[k + 1] / r.time[k]);
  };
  EXPECT_GT(local_slope(0), 1.9);                   // MSD ~ t^2
  EXPECT_LT(local_slope(r.time.size() - 2), 0.35);  // ~ ln t: slope 1/ln(t/tau0) -> 0
  // Over the last decade MSD grows like ln(1 + t/tau0), not like t.
  const double tau0 = r.enskog.tau0;
  const auto k0 = static_cast<std::size_t>(
      std::lower_bound(r.time.begin(), r.time.end(), 0.1 * r.time.back()) - r.time.begin());
  const double grow = r.msd.back() / r.msd[k0];
  const double logarithmic = std::log1p(r.time.back() / tau0) / std::log1p(r.time[k0] / tau0);
  EXPECT_NEAR(grow / logarithmic, 1.0, 0.15) << "MSD grew " << grow << "x, ln(1 + t/tau0) " << logarithmic << "x";
  for (std::size_t k = 0; k < r.lag.size(); ++k) {
    if (r.lag[k] <= 5.0) {
      EXPECT_LT(r.time_averaged_msd[k] / interpolate(r.time, r.msd, r.lag[k]), 0.5);
    }
  }
}

TEST(BrownianEdmd, SameResultOnOneAndTwoThreads) {
  const auto measure = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    Config config = gas(0.8, 2.0);
    config.set("system.count", std::int64_t{300});
    config.set("system.radius", 0.03);
    return measure_edmd_msd(config);
  };
  const auto one = measure(1), two = measure(2);
  EXPECT_EQ(one.msd, two.msd);
  EXPECT_EQ(one.time_averaged_msd, two.time_averaged_msd);
}

}  // namespace
}  // namespace granflow::scenarios
