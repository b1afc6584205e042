#pragma once
// The force on each particle at the current positions and velocities
// (soft-sphere contacts, walls, gravity), for the next kick.
#include "components/vector.hpp"
#include "engine/core/world.hpp"

namespace granflow {
template <int D>
struct Force : Column<Vec<D>> {
  static constexpr const char* key = "force";
};
}  // namespace granflow
