#pragma once
// Scenario `crater_impact`: see scenarios/crater_impact.cpp.

#include "engine/config.hpp"
#include "engine/preparation.hpp"
#include "engine/world.hpp"

namespace granflow::scenarios {

// The bed (ids 0..N-1, species 0, at rest) and the projectile (id N, species
// 1) in a reflecting unit box, as the run starts; `preparation` hears how far
// melting the bed is.
void build_crater(World& world, const Config& config, const Preparation& preparation = {});
// Radius of the bed disks that gives bed.packing_fraction.
double bed_radius(const Config& config);

}  // namespace granflow::scenarios
