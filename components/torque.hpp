#pragma once
// The torque on each sphere about its centre from the tangential contact
// forces, for the next rotational kick.
#include "components/vector.hpp"
#include "engine/core/world.hpp"

namespace granflow {
struct Torque : Column<Vec<3>> {
  static constexpr const char* key = "torque";
};
}  // namespace granflow
