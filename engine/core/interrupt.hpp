#pragma once
// SIGINT and SIGTERM ask a run to stop at its next safe point (where its
// state can be checkpointed) instead of killing it. A second signal kills
// the process as usual.

#include <atomic>

namespace granflow {

class InterruptGuard {
 public:
  InterruptGuard();   // installs the handlers
  ~InterruptGuard();  // restores the previous ones
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  const std::atomic<bool>& requested() const;
  int signal_number() const;  // 0 when none arrived
};

// For tests: behaves as if the signal had arrived.
void request_interrupt(int signal_number);

}  // namespace granflow
