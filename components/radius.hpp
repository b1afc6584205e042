#pragma once
// Hard-core radius.
#include <cstdint>

#include "engine/core/world.hpp"

namespace granflow {
struct Radius : Column<double> {
  static constexpr const char* key = "radius";
};
}  // namespace granflow
