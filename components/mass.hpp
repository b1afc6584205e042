#pragma once
// Inertial mass.
#include <cstdint>

#include "engine/core/world.hpp"

namespace granflow {
struct Mass : Column<double> {
  static constexpr const char* key = "mass";
};
}  // namespace granflow
