#pragma once
// Scenario `mixture`: see scenarios/mixture.cpp.

#include "engine/config.hpp"
#include "engine/scenario_registry.hpp"
#include "engine/world.hpp"

#include <functional>

namespace granflow::scenarios {

const ConfigSchema& mixture_schema();
int run_mixture(const Config& config, const RunOptions& options);
// Gives the heavy fraction of a built world's particles species 1 and mass_ratio x system.mass.
std::function<void(World&)> mixture_species(const Config& config);

}  // namespace granflow::scenarios
