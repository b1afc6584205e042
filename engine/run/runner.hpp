#pragma once
// Runs a registered scenario: the one place that opens the result file,
// builds the run (or every member of an ensemble), executes it, writes
// checkpoints, handles interruption and resumption, reports progress and the
// profile, and turns the outcome into an exit status.

#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/communicator.hpp"
#include "engine/core/config.hpp"
#include "engine/core/interrupt.hpp"
#include "engine/run/scenario.hpp"

namespace granflow {

struct RunOptions {
  std::string output_path;  // empty: the scenario's default
  bool profile = false;     // print the per-system table (it is always stored under /profile)
  bool progress = true;
  bool resume = false;      // continue from OUTPUT.checkpoint
  bool handle_signals = true;  // SIGINT/SIGTERM checkpoint and stop (off inside sweeps' worker threads)
  // A guard installed by the caller (a sweep), watched instead of one of the run's own.
  const InterruptGuard* interrupt_guard = nullptr;
  // A table of observables on standard error every `log_every` output rounds (0: none).
  std::int64_t log_every = 0;
  std::vector<std::string> log_observables;  // empty: the first six scalar ones
  // The ranks one system is spread over (null: this process alone). Rank 0
  // writes the result file and the checkpoints; every rank runs the same
  // loop, so that the collective calls of a distributed step match.
  Communicator* communicator = nullptr;
};

// Exit statuses of a run.
inline constexpr int exit_finished = 0;
inline constexpr int exit_bad_input = 2;
inline constexpr int exit_physics_failed = 3;  // e.g. inelastic collapse
inline int exit_interrupted(int signal_number) { return 128 + (signal_number > 0 ? signal_number : 2); }

int run_scenario(const Scenario& scenario, const Config& config, const RunOptions& options);

// A run stopped by a physical failure (e.g. inelastic collapse).
class PhysicsFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Every member of an ensemble scenario, in memory (no file, no checkpoints):
// for tests and programs that reduce the results themselves.
EnsembleResults simulate_ensemble(const Scenario& scenario, const Config& config);

// The derived seed of ensemble member r (member 0 keeps the configured seed),
// the same as a sweep's repeat r.
std::uint64_t member_seed(std::int64_t base, std::size_t member);

}  // namespace granflow
