#pragma once
// Per-particle angular velocity of a rotating sphere (three components; only
// soft spheres with tangential friction carry it).
#include "components/vector.hpp"
#include "engine/core/world.hpp"

namespace granflow {
struct AngularVelocity : Column<Vec<3>> {
  static constexpr const char* key = "angular_velocity";
};
}  // namespace granflow
