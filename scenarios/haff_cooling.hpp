#pragma once
// Homogeneous cooling of a granular gas (Haff's law), seed 000 ch. 4.1.

#include "engine/config.hpp"
#include "engine/scenario_registry.hpp"

namespace granflow::scenarios {

const ConfigSchema& haff_cooling_schema();
int run_haff_cooling(const Config& config, const RunOptions& options);

}  // namespace granflow::scenarios
