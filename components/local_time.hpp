#pragma once
// The time at which Position holds (Marin, Risso & Cordero delayed states): only particles in an event are advanced.
#include <cstdint>

#include "engine/world.hpp"

namespace granflow {
struct LocalTime : Column<double> {
  static constexpr const char* key = "local_time";
};
}  // namespace granflow
