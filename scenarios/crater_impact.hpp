#pragma once
// Scenario `crater_impact`: see scenarios/crater_impact.cpp.

#include "engine/config.hpp"
#include "engine/scenario_registry.hpp"
#include "engine/world.hpp"

namespace granflow::scenarios {

const ConfigSchema& crater_impact_schema();
int run_crater_impact(const Config& config, const RunOptions& options);

// The bed (ids 0..N-1, species 0, at rest) and the projectile (id N, species
// 1) in a reflecting unit box, as the run starts.
void build_crater(World& world, const Config& config);
// Radius of the bed disks that gives bed.packing_fraction.
double bed_radius(const Config& config);

}  // namespace granflow::scenarios
