#pragma once
// Scenario `mixture`: see scenarios/mixture.cpp.

#include <functional>

#include "engine/core/config.hpp"
#include "engine/core/world.hpp"

namespace granflow::scenarios {

// Makes the last round(heavy_fraction N) particles species 1 ("heavy"), of
// mass mixture.mass_ratio x system.mass.
std::function<void(World&)> mixture_species(const Config& config);

}  // namespace granflow::scenarios
