// Scattering angle against impact parameter from
// two-particle event-driven runs, against the analytic hard-disk result.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "scenarios/scattering.hpp"
#include "tests/scenario_schema.hpp"

namespace granflow::scenarios {
namespace {

TEST(Scattering, AnalyticAngleIsTheTextbookResultForElasticCollisions) {
  // Independent of the velocity construction in analytic_scattering_angle:
  // tan(theta) = sin(chi) / (cos(chi) + m2/m1), chi = pi - 2 asin(b/R12).
  for (double ratio : {0.0, 0.2, 0.5, 1.0 / std::numbers::sqrt2, 0.9, 0.999}) {
    const double chi = std::numbers::pi - 2.0 * std::asin(ratio);
    const double textbook = std::atan2(std::sin(chi), std::cos(chi) + 0.25);
    EXPECT_NEAR(analytic_scattering_angle(ratio, 4.0, 1.0, 1.0), textbook, 1e-12) << ratio;
  }
  // An immovable target deflects by chi: a right angle at b = R12 / sqrt(2).
  EXPECT_NEAR(analytic_scattering_angle(1.0 / std::numbers::sqrt2, 1e300, 1.0, 1.0), std::numbers::pi / 2, 1e-12);
}

void expect_scan_matches(double restitution, double target_mass) {
  Config config(scenario_schema("scattering"));
  config.set("collision.restitution", restitution);
  config.set("target.mass", target_mass);
  config.set("scan.points", std::int64_t{101});
  const auto scan = scattering_scan(config);
  ASSERT_EQ(scan.size(), 101u);
  for (const auto& p : scan) {
    // Contact times come from a quadratic solved in double precision; near
    // grazing incidence (b -> R12) the angle depends on the contact point as
    // 1/sqrt(1 - (b/R12)^2), which amplifies that round-off.
    const double tolerance = p.impact_ratio < 0.99 ? 1e-9 : 1e-5;
    EXPECT_NEAR(p.angle, p.analytic, tolerance) << "b/R12 = " << p.impact_ratio << ", xi = " << restitution;
  }
  EXPECT_NEAR(scan.front().angle, restitution > 0 ? std::numbers::pi : 0.0, 1e-9);  // head-on
  EXPECT_EQ(scan.back().angle, 0.0);  // b > R12: no collision
}

TEST(Scattering, ElasticScanMatchesAnalyticCurve) { expect_scan_matches(1.0, 1e6); }
TEST(Scattering, InelasticScanMatchesAnalyticCurve) { expect_scan_matches(0.5, 1e6); }
TEST(Scattering, ComparableMassesMatchAnalyticCurve) { expect_scan_matches(1.0, 3.0); }

}  // namespace
}  // namespace granflow::scenarios
