#pragma once
// Scenario `scattering`: a light small disk fired at a heavy large one at
// rest, for a scan of impact parameters b; the scattering angle against
// b / R12 with the analytic hard-disk result.

#include <vector>

#include "engine/config.hpp"

namespace granflow::scenarios {


struct ScatteringPoint {
  double impact_ratio;  // b / R12
  double angle;         // simulated, radians, between the incoming and outgoing velocity
  double analytic;
};

// One two-particle event-driven run per impact parameter (the members of the
// scenario's ensemble), in parallel.
std::vector<ScatteringPoint> scattering_scan(const Config& config);

// Lab-frame angle for a target of mass m1 at rest hit by m2 at impact
// parameter b = ratio * R12, with normal restitution xi: the centre-line
// component of the relative velocity is reversed and scaled by xi, the
// tangential one kept (for xi = 1: tan(theta) = sin(chi) / (cos(chi) + m2/m1),
// chi = pi - 2 asin(b/R12)).
double analytic_scattering_angle(double ratio, double m1, double m2, double restitution);

}  // namespace granflow::scenarios
