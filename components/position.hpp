#pragma once
// Per-particle positions at the particle's own LocalTime (delayed states in EDMD), wrapped into the box.
#include "components/vector.hpp"
#include "engine/world.hpp"

namespace granflow {
template <int D>
struct Position : Column<Vec<D>> {
  static constexpr const char* key = "position";
};
}  // namespace granflow
