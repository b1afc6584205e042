#pragma once
// Time of the particle's last collision, for the TC model.
#include <cstdint>

#include "engine/core/world.hpp"

namespace granflow {
struct LastCollisionTime : Column<double> {
  static constexpr const char* key = "last_collision_time";
};
}  // namespace granflow
