#pragma once
// Runs the points of a sweep concurrently (one World per point, oneTBB tasks
// on `workers` threads), skips points whose result file is already complete,
// and writes the summary tables: per run (summary_runs.csv) and per parameter
// point with mean and standard error over repeats (summary.csv), both also in
// summary.h5.

#include <string>

#include "engine/sweep_plan.hpp"

namespace granflow {

struct SweepOptions {
  int workers = 0;  // 0: all cores
  bool progress = true;
};

// Exit status: 0 when every point finished, 3 when a point stopped on a
// physical failure or threw (the others still run and are summarised).
int run_sweep(const SweepPlan& plan, const SweepOptions& options);

}  // namespace granflow
