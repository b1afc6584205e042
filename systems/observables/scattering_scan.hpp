#pragma once
// A scan of two-disk collisions over the impact parameter b: the simulated
// scattering angle of the light disk (ScatteringAngleObserver) against the
// analytic one, written as /results datasets with the analytic curve on a
// fine grid for drawing it between the scan's points.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/units.hpp"
#include "engine/io/h5md_file.hpp"

namespace granflow {

struct ScatteringPoint {
  double impact_ratio;  // b / R12
  double angle;         // simulated, radians, between the incoming and outgoing velocity
  double analytic;
};

// Lab-frame angle for a target of mass m1 at rest hit by m2 at impact
// parameter b = ratio * R12, with normal restitution xi: the centre-line
// component of the relative velocity is reversed and scaled by xi, the
// tangential one kept (for xi = 1: tan(theta) = sin(chi) / (cos(chi) + m2/m1),
// chi = pi - 2 asin(b/R12)).
inline double analytic_scattering_angle(double ratio, double m1, double m2, double restitution) {
  if (ratio >= 1.0) return 0.0;
  // Unit vector from the small particle's centre to the large one's at contact.
  const double nx = std::sqrt(1.0 - ratio * ratio), ny = -ratio;
  const double push = (1.0 + restitution) * m1 / (m1 + m2) * nx;  // (v . n) with v = (1, 0)
  const double vx = 1.0 - push * nx, vy = -push * ny;
  return std::atan2(std::abs(vy), vx);
}

// impact_parameter_ratio, scattering_angle and scattering_angle_analytic
// per point; analytic_curve_* on 1001 ratios up to the largest; the
// largest deviation as attribute largest_deviation_rad of /observables.
inline void write_scattering_scan(H5mdFile& file, const std::vector<ScatteringPoint>& scan, double m1, double m2,
                                  double restitution) {
  std::vector<double> ratio, angle, analytic;
  double worst = 0.0;
  for (const auto& p : scan) {
    ratio.push_back(p.impact_ratio);
    angle.push_back(p.angle);
    analytic.push_back(p.analytic);
    worst = std::max(worst, std::abs(p.angle - p.analytic));
  }
  file.write_result("impact_parameter_ratio", ratio, unit::none);
  file.write_result("scattering_angle", angle, unit::angle);
  file.write_result("scattering_angle_analytic", analytic, unit::angle);
  const double largest = ratio.empty() ? 1.0 : *std::max_element(ratio.begin(), ratio.end());
  std::vector<double> fine_ratio, fine_angle;
  for (int k = 0; k <= 1000; ++k) {
    fine_ratio.push_back(largest * k / 1000.0);
    fine_angle.push_back(analytic_scattering_angle(fine_ratio.back(), m1, m2, restitution));
  }
  file.write_result("analytic_curve_impact_parameter_ratio", fine_ratio, unit::none);
  file.write_result("analytic_curve_scattering_angle", fine_angle, unit::angle);
  file.write_attribute("/observables", "largest_deviation_rad", worst);
  spdlog::info("{} impact parameters, largest deviation from the analytic angle {:.3g} rad", ratio.size(), worst);
}

}  // namespace granflow
