#pragma once
// What the driver of a run asks of the time-advancing system (reach the next
// output time) and what that system answers (stop, and why).

#include <cstdint>
#include <limits>
#include <string>

namespace granflow {

struct RunControl {
  static constexpr const char* key = "run_control";
  double target_time = 0.0;
  // Event-driven runs also pause here (e.g. to sample every few collisions
  // per particle); reaching it is not a stop.
  std::uint64_t pause_at_pair_collisions = std::numeric_limits<std::uint64_t>::max();
  bool stop = false;
  bool failed = false;  // stopped on an error (e.g. inelastic collapse), not a stop criterion
  std::string reason;
};

}  // namespace granflow
