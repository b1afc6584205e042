#pragma once
// Runs the points of a sweep concurrently (one World per point, oneTBB tasks
// on `workers` threads), skips points whose result file is already complete,
// and writes the summary tables: per run (summary_runs.csv) and per parameter
// point with mean and standard error over repeats (summary.csv), both also in
// summary.h5. Beside each result file a one-line status (RESULT.status: done,
// stopped (exit N), or failed and why), so that the summary can be built
// later from the files alone: with a shard, only that shard's runs are run
// and no summary is written; `collect` runs nothing and writes the summary
// of what all shards left, naming what is missing or failed.

#include <atomic>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "engine/app/sweep_plan.hpp"
#include "engine/app/sweep_shards.hpp"
#include "engine/core/config.hpp"
#include "engine/core/interrupt.hpp"
#include "engine/run/progress.hpp"

namespace granflow {

struct SweepOptions {
  int workers = 0;  // 0: all cores
  bool progress = true;
  Shard shard;           // count 0: the whole sweep
  bool collect = false;  // only build the summary from the result files
};

// Exit status: 0 when every point (of the shard) finished, 3 when a point
// stopped on a physical failure, threw, or (collect) has no result (the
// others still run and are summarised); 130 / 143 when SIGINT / SIGTERM
// stopped it: the runs under way are checkpointed, and the same command
// continues the sweep.
int run_sweep(const SweepPlan& plan, const SweepOptions& options);

// The pieces of run_sweep that a sweep spread over MPI ranks shares.

// The runs one invocation owes (all of them, or a shard's) and what is known
// of each.
struct SweepWork {
  std::vector<bool> mine;           // run k belongs to this invocation
  std::vector<std::string> status;  // done, stopped (exit N), failed, pending; missing (collect)
  std::vector<std::size_t> todo;    // runs still to do, longest expected first
  std::size_t assigned = 0;         // runs of this invocation, finished or not
  bool summary_checked = false;     // summary names checked against a result file
};

// Creates the result directory and reads what earlier attempts left.
SweepWork survey_sweep(const SweepPlan& plan, const SweepOptions& options);

// workers: how the runs are spread ("2 workers", "3 ranks x 2 workers").
void log_sweep_start(const SweepPlan& plan, const SweepOptions& options, const SweepWork& work,
                     const std::string& workers);

// Runs plan.runs[k] into its result file and records its outcome beside it;
// returns the outcome (a failure is logged, never thrown). A run with a
// checkpoint of its own configuration (an interrupted attempt) continues
// from it. With `guard`, a signal stops the run at its next safe point with
// a checkpoint: the outcome is then "interrupted" and nothing is recorded.
std::string execute_sweep_run(const SweepPlan& plan, std::size_t k, const InterruptGuard* guard = nullptr);

// Takes the outcomes of runs as they finish (one caller at a time): each
// run's status, the summary names checked against the first result, and the
// progress line.
class SweepTally {
 public:
  SweepTally(const SweepPlan& plan, SweepWork& work, bool show_progress);
  void record(std::size_t run, const std::string& outcome);
  // A summary name is not an observable of the results: start no more runs.
  bool abandoned() const { return abandoned_; }
  // Once the last run is in: ends the progress line, and throws the
  // ConfigError naming the summary name if there was one.
  void finish();
  // Ends the progress display of an interrupted sweep (no summary).
  void interrupt();

 private:
  const SweepPlan& plan_;
  SweepWork& work_;
  Progress progress_;
  std::size_t done_ = 0;
  std::atomic<bool> abandoned_{false};
  std::optional<ConfigError> summary_error_;
};

// Once every run of `work` has an outcome: the shard record or the summary
// tables, and the exit status.
int conclude_sweep(const SweepPlan& plan, const SweepOptions& options, const SweepWork& work);

}  // namespace granflow
