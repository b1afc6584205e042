#pragma once
// Stable particle identity; storage order changes when particles are sorted in space.
#include <cstdint>

#include "engine/core/world.hpp"

namespace granflow {
struct ParticleId : Column<std::uint32_t> {
  static constexpr const char* key = "particle_id";
};
}  // namespace granflow
