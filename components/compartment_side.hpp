#pragma once
// Which side of a divider a sphere was on when it was last looked at: 0 not
// yet, 1 left, 2 right. Kept as a column, not by an observer, so that it
// follows its sphere wherever the spheres are reordered, checkpointed or
// passed to another rank, and a crossing is counted where the sphere is.
#include <cstdint>

#include "engine/core/world.hpp"

namespace granflow {
struct CompartmentSide : Column<std::uint8_t> {
  static constexpr const char* key = "compartment_side";
};
}  // namespace granflow
