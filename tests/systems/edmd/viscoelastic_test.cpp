// Viscoelastic spheres in the event-driven gas:
//  * eps(b) of the integrated collision against its published expansion
//    1 - C1 b + C2 b^2 (Ramirez et al. 1999; C1 = 1.15345 in closed form,
//    C2 = 3/5 C1^2): the remainder stays below 0.5 b^5/2 (the next term of
//    the series, from the delayed recovery, is of that order), which a C2
//    off by 0.02 would break at b = 10^-3; the table against the integration
//    within 10^-6 over its range;
//  * cooling (haff_cooling, N = 4000, g_ve = 10^7, so eps = 0.97 at the start
//    and -> 1): ln T against ln t from 100 tau to the end within 5 % of
//    -5/3 (measured -1.672), T within 15 % of the first-order theory
//    (1 + t/tau)^-5/3 at all times (measured up to +9 %, slower: the theory
//    keeps only the first order in b, and, as for constant restitution,
//    velocity correlations slow the cooling);
//  * self-diffusion (brownian_edmd, 4 x 1000 particles, to t = 10^6): the
//    MSD fitted as c + a t^gamma over t >= 100 tau has gamma within 5 % of
//    1/6 (measured 0.166).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "scenarios/brownian_edmd.hpp"
#include "systems/edmd/viscoelastic_restitution.hpp"
#include "systems/observables/least_squares.hpp"
#include "tests/scenario_run.hpp"
#include "tests/scenario_schema.hpp"

namespace granflow {
namespace {

TEST(Viscoelastic, IntegratedCollisionFollowsThePublishedExpansion) {
  const double c1 = edmd::viscoelastic_c1(), c2 = edmd::viscoelastic_c2();
  EXPECT_NEAR(c1, 1.15345, 1e-5);
  EXPECT_NEAR(c2, 0.79827, 1e-5);
  for (double b : {1e-3, 3e-3, 1e-2, 3e-2}) {
    const double eps = edmd::viscoelastic_restitution_integrated(b, 2e-5);
    const double remainder = eps - (1.0 - c1 * b + c2 * b * b);
    EXPECT_LT(std::abs(remainder), 0.5 * std::pow(b, 2.5)) << "b = " << b << ": eps = " << eps;
  }
  // Stronger damping, lower restitution; b -> 0 is elastic.
  EXPECT_EQ(edmd::viscoelastic_restitution_integrated(0.0), 1.0);
  EXPECT_GT(edmd::viscoelastic_restitution_integrated(0.5), edmd::viscoelastic_restitution_integrated(1.0));
  EXPECT_GT(edmd::viscoelastic_restitution_integrated(3.0), 0.0);
}

TEST(Viscoelastic, TableMatchesTheIntegration) {
  const edmd::ViscoelasticRestitution eps(2.0);
  double worst = 0.0;
  for (double b = 1e-4; b < 4.0; b *= 1.37) {
    const double g = 2.0 * std::pow(b, 5.0);
    worst = std::max(worst, std::abs(eps(g) - edmd::viscoelastic_restitution_integrated(b, 2e-5)));
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(eps(0.0), 1.0);
  EXPECT_FALSE(edmd::ViscoelasticRestitution(0.0).on());
}

H5mdReader run(const std::string& scenario, const Config& config, const std::string& name) {
  static const ScratchDirectory scratch("granflow_viscoelastic_");
  return run_scenario_in(scratch, scenario, config, name);
}

TEST(Viscoelastic, HaffLawOfViscoelasticSpheres) {
  Config config(scenario_schema("haff_cooling"));
  config.set("system.count", std::int64_t{4000});
  config.set("collision.restitution", 1.0);
  config.set("collision.viscoelastic_speed", 1e7);
  config.set("run.t_stop", 1e6);
  config.set("output.spacing", std::string("log"));
  const auto file = run("haff_cooling", config, "haff");
  const double tau = file.double_attribute("/parameters/derived", "haff_tau0");
  EXPECT_EQ(file.double_attribute("/parameters/derived", "haff_exponent"), 5.0 / 3.0);
  const auto t = file.doubles("/observables/temperature/time").values;
  const auto temperature = file.doubles("/observables/temperature/value").values;
  LineFit late;
  double worst = 0.0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    const double ratio = temperature[k] / temperature[0];
    worst = std::max(worst, std::abs(ratio / std::pow(1.0 + t[k] / tau, -5.0 / 3.0) - 1.0));
    if (t[k] >= 100 * tau) late.add(std::log(t[k]), std::log(ratio));
  }
  std::printf("tau = %.4g; ln T ~ %.4f ln t over [100 tau, %.3g tau] (%zu outputs); largest departure from the "
              "first-order theory %.1f %%\n",
              tau, late.slope(), t.back() / tau, late.points(), 100 * worst);
  ASSERT_GT(late.points(), 20u);
  EXPECT_NEAR(late.slope(), -5.0 / 3.0, 0.05 * 5.0 / 3.0);
  EXPECT_LT(worst, 0.15);
}

TEST(Viscoelastic, MeanSquaredDisplacementGrowsAsTheSixthRootOfTime) {
  Config config(scenario_schema("brownian_edmd"));
  config.set("collision.restitution", 1.0);
  config.set("collision.viscoelastic_speed", 1e7);
  config.set("run.t_stop", 1e6);
  config.set("msd.sample_interval", 1000.0);
  const auto result = scenarios::measure_edmd_msd(config);
  std::printf("MSD = c + a t^gamma over t >= 100 tau (tau = %.4g): gamma = %.4f\n", result.enskog.tau0,
              result.msd_exponent);
  EXPECT_NEAR(result.msd_exponent, 1.0 / 6.0, 0.05 / 6.0);
}

}  // namespace
}  // namespace granflow
