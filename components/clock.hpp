#pragma once
// Simulation time, and the step counter used to label output frames.
#include <cstdint>

namespace granflow {
struct Clock {
  static constexpr const char* key = "clock";
  double time = 0.0;
  std::int64_t step = 0;
};
}  // namespace granflow
