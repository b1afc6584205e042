// SDE stepping against theory (Langevin and UDSBM moments, Bodrova et al. 2016):
// the closed forms of the MSD against the exact moment equations, the exact
// Ornstein-Uhlenbeck update against the stationary variance, simulated
// ensemble MSDs against theory within their standard error, ergodicity of
// Langevin dynamics and its breaking by UDSBM, the better scheme against
// Euler-Maruyama at a large step, and independence of the thread count.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "components/clock.hpp"
#include "engine/core/rng.hpp"
#include "engine/run/run_control.hpp"
#include "scenarios/sde_msd.hpp"
#include "systems/sde/gaussian_noise.hpp"
#include "systems/sde/sde_parameters.hpp"
#include "systems/sde/sde_step.hpp"
#include "systems/sde/sde_theory.hpp"
#include "tests/scenario_schema.hpp"

namespace granflow::sde {
namespace {

SdeModel gas_model(double restitution) {
  return model_from_gas(1000, 0.025, restitution, 2.0 / 3.0, 1.0, 1.0);
}

TEST(GaussianNoise, PhiloxMatchesRandom123AndNormalsHaveGaussianMoments) {
  double sum = 0, squares = 0, fourth = 0;
  constexpr std::uint64_t draws = 500000;
  for (std::uint64_t item = 0; item < draws; ++item) {
    const std::uint64_t seed = 0x123456789abcdefULL + item;
    const auto expected = Philox(stream::sde_noise, seed, item * 3, item).next_words();
    std::uint32_t c0 = static_cast<std::uint32_t>(item), c1 = static_cast<std::uint32_t>(item >> 32);
    std::uint32_t c2 = static_cast<std::uint32_t>(item * 3), c3 = stream::sde_noise << 16;
    philox4x32_10(c0, c1, c2, c3, static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32));
    ASSERT_EQ(expected, (std::array<std::uint32_t, 4>{c0, c1, c2, c3})) << item;
    const float r = box_muller_radius(c0), angle = box_muller_angle(c1);
    for (double z : {r * std::cos(angle), r * std::sin(angle)}) {
      sum += z;
      squares += z * z;
      fourth += z * z * z * z;
    }
  }
  const double n = 2.0 * draws;
  // Standard errors: 1/sqrt(n) for the mean, sqrt(2/n) for the variance, sqrt(96/n) for the 4th moment.
  EXPECT_NEAR(sum / n, 0.0, 4.0 / std::sqrt(n));
  EXPECT_NEAR(squares / n, 1.0, 4.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(fourth / n, 3.0, 4.0 * std::sqrt(96.0 / n));
}

TEST(SdeTheory, ClosedFormsSolveTheMomentEquations) {
  const std::vector<double> times{0.001, 0.01, 0.1, 1.0, 10.0, 100.0};
  SdeModel langevin = gas_model(1.0);
  ASSERT_FALSE(langevin.scaled());
  // Enskog: 6 D0 = 0.350 for this gas (N = 1000, r = 0.025, L = 1, T0 = 2/3).
  EXPECT_NEAR(6 * langevin.diffusivity0, 0.350, 0.001);
  const auto l = moment_msd(langevin, langevin.stationary_velocity_variance(), times);
  for (std::size_t k = 0; k < times.size(); ++k) EXPECT_NEAR(l[k] / langevin_msd(langevin, times[k]), 1.0, 1e-7);
  // The closed form for any initial variance: against the integrated moment
  // equations once several 1/gamma have passed (the integrator's first steps
  // are off by ~(gamma h)^2), and against the Taylor series
  // v2 t^2 + (2 D gamma^2 - 3 gamma v2) t^3 / 3 at gamma t = 1e-3, whose next
  // term is smaller by ~gamma t.
  const std::vector<double> late{1.0, 10.0, 100.0};
  const double g = langevin.gamma0, d = langevin.diffusivity0, t = 1e-3 / langevin.gamma0;
  for (double v2 : {0.0, 0.2, 3.0}) {
    const auto closed = moment_msd(langevin, v2, late);
    const auto integrated = integrated_moment_msd(langevin, v2, late);
    for (std::size_t k = 0; k < late.size(); ++k) EXPECT_NEAR(closed[k] / integrated[k], 1.0, 1e-7) << v2;
    const double series = v2 * t * t + (2 * d * g * g - 3 * g * v2) * t * t * t / 3;
    EXPECT_NEAR(langevin_moment_msd(langevin, v2, t) / series, 1.0, 3e-3) << v2;
  }
  SdeModel udsbm = gas_model(0.8);
  ASSERT_TRUE(udsbm.scaled());
  const auto u = moment_msd(udsbm, udsbm.stationary_velocity_variance(), times);
  for (std::size_t k = 0; k < times.size(); ++k) EXPECT_NEAR(u[k] / udsbm_msd(udsbm, times[k]), 1.0, 1e-7);
}

TEST(SdeTheory, ExactUpdateKeepsTheStationaryVariance) {
  for (double xi : {1.0, 0.8, 0.5}) {
    const SdeModel m = gas_model(xi);
    for (double t : {0.0, 0.3, 7.0, 120.0})
      for (double h : {1e-3, 0.05, 2.0}) {
        const auto ou = exact_velocity_update(m, t, h);
        const double propagated = ou.decay * ou.decay * m.stationary_velocity_variance(t) + ou.spread * ou.spread;
        EXPECT_NEAR(propagated / m.stationary_velocity_variance(t + h), 1.0, 1e-12) << xi << " " << t << " " << h;
      }
  }
}

// The standard error is estimated from the scatter of `runs` runs: 16 runs
// (15 degrees of freedom) make that estimate good to ~20 %.
Config sde_config(const std::string& scenario, std::int64_t count, double t_stop, double dt, std::int64_t runs = 16) {
  Config config(scenario == "langevin_msd" ? scenario_schema("langevin_msd") : scenario_schema("udsbm_msd"));
  config.set("system.count", count);
  config.set("run.t_stop", t_stop);
  config.set("run.dt", dt);
  config.set("run.runs", runs);
  config.set("msd.time_average_particles", std::int64_t{500});
  return config;
}

// Largest |simulated - theory| in units of the standard error over runs,
// allowing a relative slack for the discretisation, from ten steps on: over
// the first steps the splitting's half drifts are off by O(gamma dt) (-3 %
// after one step at gamma dt = 0.11), which 16000 particles resolve.
double worst_deviation(const scenarios::SdeMsdResult& r, double slack, double dt) {
  double worst = 0.0;
  for (std::size_t k = 0; k < r.time.size(); ++k)
    if (r.time[k] >= 10 * dt * (1 - 1e-9))
    worst = std::max(worst, std::abs(r.msd[k] - r.msd_theory[k]) / (r.msd_stderr[k] + slack * r.msd_theory[k]));
  return worst;
}

TEST(SdeMsd, LangevinMatchesTheoryAndIsErgodic) {
  const auto r = scenarios::measure_sde_msd(sde_config("langevin_msd", 1000, 20.0, 0.01));
  // ~35 correlated output times: 4 standard errors bound the largest of them.
  EXPECT_LT(worst_deviation(r, 1e-3, 0.01), 4.0);
  // Ergodic: the time average over a run of 20 equals the ensemble MSD at lags << 20.
  const SdeModel m = sde_model_from(sde_config("langevin_msd", 1, 1, 1));
  for (std::size_t k = 0; k < r.lag.size(); ++k) {
    if (r.lag[k] > 1.0) break;
    EXPECT_NEAR(r.time_averaged_msd[k] / (3 * langevin_msd(m, r.lag[k])), 1.0, 0.03) << "lag " << r.lag[k];
    EXPECT_LT(r.ergodicity_breaking[k], 0.1) << "lag " << r.lag[k];
  }
}

TEST(SdeMsd, OneAndTwoDimensionsMatchTheory) {
  for (std::int64_t dimension : {1, 2}) {
    Config config = sde_config("udsbm_msd", 1000, 10.0, 0.01);
    config.set("system.dimension", dimension);
    const auto r = scenarios::measure_sde_msd(config);
    EXPECT_LT(worst_deviation(r, 1e-3, 0.01), 4.0) << dimension << "D";
    EXPECT_NEAR(r.msd_theory.back() / (static_cast<double>(dimension) / 3.0 *
                                       scenarios::measure_sde_msd(sde_config("udsbm_msd", 10, 10.0, 0.01, 1))
                                           .msd_theory.back()),
                1.0, 1e-12);
  }
}

TEST(SdeMsd, UdsbmMatchesTheoryAndIsNotErgodic) {
  const auto r = scenarios::measure_sde_msd(sde_config("udsbm_msd", 1000, 50.0, 0.01));
  EXPECT_LT(worst_deviation(r, 1e-3, 0.01), 4.0);
  const SdeModel m = sde_model_from(sde_config("udsbm_msd", 1, 1, 1));
  // Scaled Brownian motion ages: over a long measurement most of the time is
  // spent where D has decayed, so the time average at a lag falls far
  // below the ensemble MSD at that time.
  bool checked = false;
  for (std::size_t k = 0; k < r.lag.size(); ++k) {
    if (r.lag[k] < 0.5 || r.lag[k] > 1.0) continue;
    const double ratio = r.time_averaged_msd[k] / (3 * udsbm_msd(m, r.lag[k]));
    EXPECT_LT(ratio, 0.5) << "lag " << r.lag[k];
    checked = true;
  }
  EXPECT_TRUE(checked);
}

TEST(SdeMsd, ExactUpdateIsAccurateWhereEulerMaruyamaIsNot) {
  // gamma0 dt = 0.29. Euler-Maruyama's velocity variance is 1/(1 - gamma dt / 2)
  // = 1.17 times too large, which shows in the ballistic part of the MSD.
  // The exact velocity update keeps the variance exact; its half drifts give
  // a long-time diffusivity (gamma dt / 2) coth(gamma dt / 2) = 1 + 0.7 % of D0.
  Config config = sde_config("langevin_msd", 5000, 2.0, 0.025);
  config.set("msd.time_average_particles", std::int64_t{0});
  const auto exact = scenarios::measure_sde_msd(config);
  config.set("run.scheme", std::string("euler_maruyama"));
  const auto euler = scenarios::measure_sde_msd(config);
  double worst_exact = 0.0, worst_euler = 0.0;
  // A splitting scheme resolves times of two steps and more (after one step
  // the half drifts give (1 + decay)/2 of the ballistic MSD).
  for (std::size_t k = 0; k < exact.time.size(); ++k) {
    if (exact.time[k] < 2 * 0.025 * (1 - 1e-9)) continue;
    worst_exact = std::max(worst_exact, std::abs(exact.msd[k] / exact.msd_theory[k] - 1.0));
    worst_euler = std::max(worst_euler, std::abs(euler.msd[k] / euler.msd_theory[k] - 1.0));
  }
  std::printf("gamma0 dt = 0.29: largest relative MSD error exact-OU %.4f, Euler-Maruyama %.4f\n", worst_exact,
              worst_euler);
  EXPECT_LT(worst_exact, 0.02);
  EXPECT_GT(worst_euler, 0.045);
}

TEST(SdeMsd, ThreadCountDoesNotChangeTrajectories) {
  const auto trajectory = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    World world(50000);
    world.add_component<Position<3>>().values.assign(world.size(), Vec<3>::Zero());
    auto& v = world.add_component<Velocity<3>>();
    for (std::size_t i = 0; i < world.size(); ++i) v[i] = Vec<3>(1.0, -0.5, 0.25);
    world.emplace_resource<Clock>();
    world.emplace_resource<RunControl>().target_time = 0.2;
    SdeAdvance<3> step(gas_model(0.8), Scheme::exact_ou, 0.01, 7);
    step.run(world);
    return world.component<Position<3>>().values;
  };
  const auto one = trajectory(1), two = trajectory(2);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], two[i]) << i;
}

}  // namespace
}  // namespace granflow::sde
