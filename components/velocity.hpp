#pragma once
// Per-particle velocities.
#include "components/vector.hpp"
#include "engine/core/world.hpp"

namespace granflow {
template <int D>
struct Velocity : Column<Vec<D>> {
  static constexpr const char* key = "velocity";
};
}  // namespace granflow
