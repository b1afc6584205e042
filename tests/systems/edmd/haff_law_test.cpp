// Haff's law (Haff 1983) for a 3D granular gas, averaged
// over independent runs.
//
// Tolerance: Haff's law is the homogeneous-cooling prediction with Enskog's
// collision frequency. A correct code cools slightly slower than that at
// this density: velocity correlations and slowly growing shear modes put an
// established code 2.8 % above Haff's law at t = tau0 and 7 % above at
// 10 tau0 (N = 2048, eta = 0.067, xi = 0.7); the Sonine correction pulls the
// other way by under 1 % for xi >= 0.5. Both effects grow with time and with
// inelasticity (measured here at N = 4000: +1.3 % / +2.7 % at tau0 / 10 tau0
// for xi = 0.9, +3.3 % / +12 % for xi = 0.5). So we require
//   -(1 % + 3 se) <= T/T_Haff - 1 <= bound(t) + 3 se,
// bound = 5 % up to tau0, 10 % at 3 tau0, 20 % at 10 tau0, with the standard
// error se of the mean taken from the spread of the runs; and, since a
// correct code cools a little slower than Haff's law, a positive deviation at
// 10 tau0.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "systems/edmd/event_driven_gas.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "tests/scenario_schema.hpp"

namespace granflow::edmd {
namespace {

struct HaffCase {
  double restitution;
  std::int64_t particles;
  int runs;
};

// T(t)/T0 at t = tau0 * multiples, for each run.
std::vector<std::vector<double>> cooling_curves(const HaffCase& c, const std::vector<double>& multiples,
                                                double& tau0) {
  std::vector<std::vector<double>> curves;
  for (int run = 0; run < c.runs; ++run) {
    Config config(scenario_schema("haff_cooling"));
    config.set("system.count", c.particles);
    // radius for the default packing fraction 0.0654 at this N
    config.set("system.radius", theory::radius_for_packing_fraction<3>(static_cast<double>(c.particles), 0.0654, 1.0));
    config.set("collision.restitution", c.restitution);
    config.set("run.seed", std::int64_t{100 + run});
    World world;
    build_gas<3>(world, config, 100 + run);
    const double n = static_cast<double>(c.particles);
    const double t0_temperature = 2.0 / 3.0 * total_kinetic_energy<3>(world) / n;
    const double radius = config.real("system.radius");
    const double eta = theory::packing_fraction<3>(n, radius, 1.0);
    tau0 = theory::haff_time<3>(c.restitution, theory::collision_frequency<3>(n, 2 * radius, t0_temperature, 1.0, eta));
    EventDrivenGas<3> gas(world, CollisionParameters::from(config));
    gas.start(0.0);
    std::vector<double> curve;
    for (double m : multiples) {
      EXPECT_EQ(gas.advance(m * tau0), StopReason::reached_time);
      gas.synchronize(m * tau0);
      curve.push_back(2.0 / 3.0 * gas.kinetic_energy() / n / t0_temperature);
    }
    curves.push_back(curve);
  }
  return curves;
}

void expect_haff(const HaffCase& c) {
  const std::vector<double> multiples{0.3, 1.0, 3.0, 10.0};
  const std::vector<double> upper_bound{0.05, 0.05, 0.10, 0.20};
  double tau0 = 0;
  const auto curves = cooling_curves(c, multiples, tau0);
  for (std::size_t k = 0; k < multiples.size(); ++k) {
    double mean = 0, square = 0;
    for (const auto& curve : curves) mean += curve[k];
    mean /= c.runs;
    for (const auto& curve : curves) square += (curve[k] - mean) * (curve[k] - mean);
    const double standard_error = std::sqrt(square / (c.runs - 1) / c.runs);
    const double haff = theory::haff_temperature_ratio(multiples[k] * tau0, tau0);
    const double deviation = mean / haff - 1.0;
    const double relative_error = standard_error / haff;
    EXPECT_GE(deviation, -0.01 - 3 * relative_error) << "xi " << c.restitution << " t = " << multiples[k] << " tau0";
    EXPECT_LE(deviation, upper_bound[k] + 3 * relative_error)
        << "xi " << c.restitution << " t = " << multiples[k] << " tau0";
    if (k + 1 == multiples.size()) {
      EXPECT_GT(deviation, 0.0) << "xi " << c.restitution << " cools faster than Haff";
    }
    std::printf("xi %.2f  t/tau0 %5.1f  T/T0 %.5f  Haff %.5f  deviation %+.2f%% +- %.2f%%\n", c.restitution,
                multiples[k], mean, haff, 100 * deviation, 100 * relative_error);
  }
}

// The CI variant uses N = 4000; the `long` variant (GRANFLOW_LONG set, the
// ctest label long) N = 10^5, where finite-size effects are smaller, and
// adds xi = 0.7 (HaffLawLong, only in the long set) for comparison with the
// published +2.8 % (tau0) / +7 % (10 tau0).
std::int64_t haff_particles() { return std::getenv("GRANFLOW_LONG") ? 100000 : 4000; }
TEST(HaffLawLong, Restitution07) { expect_haff({0.7, 100000, 4}); }
TEST(HaffLaw, Restitution09) { expect_haff({0.9, haff_particles(), 4}); }
TEST(HaffLaw, Restitution05) { expect_haff({0.5, haff_particles(), 4}); }

}  // namespace
}  // namespace granflow::edmd
