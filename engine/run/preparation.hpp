#pragma once
// A long phase of making an initial state (random placement, an elastic
// equilibration, melting a lattice): it shows how far it is, like the run's
// own progress, and stops soon after SIGINT/SIGTERM instead of running to
// its end first. Nothing of a preparation is checkpointed, so an
// interrupted one leaves nothing to resume.

#include <atomic>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

namespace granflow {

class PreparationInterrupted : public std::runtime_error {
 public:
  explicit PreparationInterrupted(const std::string& phase) : std::runtime_error("interrupted during " + phase) {}
};

struct Preparation {
  std::string phase;
  std::function<void(const std::string& phase, double fraction)> report;
  const std::atomic<bool>* interrupt = nullptr;

  // The same reporting and interruption for another phase.
  Preparation named(std::string other) const { return {std::move(other), report, interrupt}; }
  void progress(double fraction) const {
    if (report) report(phase, fraction);
  }
  bool interrupted() const { return interrupt && interrupt->load(std::memory_order_relaxed); }
  // Throws PreparationInterrupted where an interruption was asked for.
  void stop_if_interrupted() const {
    if (interrupted()) throw PreparationInterrupted(phase);
  }
};

}  // namespace granflow
