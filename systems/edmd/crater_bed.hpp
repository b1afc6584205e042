#pragma once
// The crater problem's initial state: N equal disks of a melted lattice
// filling y < bed.height of a reflecting unit box at bed.packing_fraction,
// at rest, and a projectile above them moving straight down.

#include "engine/core/config.hpp"
#include "engine/core/world.hpp"
#include "engine/run/preparation.hpp"

namespace granflow::edmd {

// The bed (ids 0..N-1, species 0, at rest) and the projectile (id N, species
// 1) in a reflecting unit box, as the run starts; `preparation` hears how far
// melting the bed is.
void build_crater(World& world, const Config& config, const Preparation& preparation = {});
// Radius of the bed disks that gives bed.packing_fraction.
double bed_radius(const Config& config);

}  // namespace granflow::edmd
