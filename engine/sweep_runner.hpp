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

#include <string>

#include "engine/sweep_plan.hpp"
#include "engine/sweep_shards.hpp"

namespace granflow {

struct SweepOptions {
  int workers = 0;  // 0: all cores
  bool progress = true;
  Shard shard;           // count 0: the whole sweep
  bool collect = false;  // only build the summary from the result files
};

// Exit status: 0 when every point (of the shard) finished, 3 when a point
// stopped on a physical failure, threw, or (collect) has no result (the
// others still run and are summarised).
int run_sweep(const SweepPlan& plan, const SweepOptions& options);

}  // namespace granflow
