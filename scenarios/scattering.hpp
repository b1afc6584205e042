#pragma once
// Scenario `scattering`: a light small disk fired at a heavy large one at
// rest, for a scan of impact parameters b; the scattering angle against
// b / R12 with the analytic hard-disk result.

#include <vector>

#include "engine/core/config.hpp"
#include "systems/observables/scattering_scan.hpp"

namespace granflow::scenarios {

// One two-particle event-driven run per impact parameter (the members of the
// scenario's ensemble), in parallel.
std::vector<ScatteringPoint> scattering_scan(const Config& config);

}  // namespace granflow::scenarios
