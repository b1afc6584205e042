#pragma once
// What the Runner asks of the systems that advance time (reach the next
// target time or step) and what they answer (stop, and why). The step is the
// Clock's counter: time steps for time-stepped methods, pair collisions for
// event-driven ones.

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

namespace granflow {

struct RunControl {
  static constexpr const char* key = "run_control";
  double target_time = 0.0;
  std::int64_t target_step = std::numeric_limits<std::int64_t>::max();
  bool stop = false;
  bool failed = false;  // stopped on an error (e.g. inelastic collapse), not a stop criterion
  std::string reason;
  // True while the observers of the run's final round run (triggers with at_end()).
  bool ending = false;
  // Set when the user asked the run to stop (SIGINT/SIGTERM); a long advance
  // may return early, at a point where its state can be saved.
  const std::atomic<bool>* interrupt = nullptr;
  bool interrupted() const { return interrupt && interrupt->load(std::memory_order_relaxed); }
  // Stops the run on a physical failure; the first failure's reason stands.
  void fail(std::string why) {
    if (failed) return;
    stop = failed = true;
    reason = std::move(why);
  }
};

}  // namespace granflow
