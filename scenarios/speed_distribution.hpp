#pragma once
// Scenario `speed_distribution`: see scenarios/speed_distribution.cpp.

#include "engine/config.hpp"
#include "engine/scenario_registry.hpp"

namespace granflow::scenarios {

const ConfigSchema& speed_distribution_schema();
int run_speed_distribution(const Config& config, const RunOptions& options);

}  // namespace granflow::scenarios
