#pragma once
// Number of events that changed the particle's velocity; a prediction made against a partner is valid only while the partner's count is unchanged.
#include <cstdint>

#include "engine/core/world.hpp"

namespace granflow {
struct CollisionCount : Column<std::uint32_t> {
  static constexpr const char* key = "collision_count";
};
}  // namespace granflow
