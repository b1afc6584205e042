#pragma once
// Simulation time, and the step counter used to label output frames.
#include <cstdint>

namespace granflow {
struct Clock {
  static constexpr const char* key = "clock";
  double time = 0.0;
  std::int64_t step = 0;

  // One step of a fixed-step method: the time is counted in steps, not
  // summed, so that output times land on steps exactly.
  void advance(double dt) {
    ++step;
    time = static_cast<double>(step) * dt;
  }
};
}  // namespace granflow
