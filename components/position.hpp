#pragma once
// Per-particle positions, wrapped into the box; up to date after an engine synchronises.
#include "components/vector.hpp"
#include "engine/core/world.hpp"

namespace granflow {
template <int D>
struct Position : Column<Vec<D>> {
  static constexpr const char* key = "position";
};
}  // namespace granflow
