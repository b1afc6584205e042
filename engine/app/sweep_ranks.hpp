#pragma once
// A sweep spread over the ranks of an MPI job (`mpirun -np K granflow sweep
// FILE`, built with -DGRANFLOW_MPI=ON). Rank 0 deals the runs out one at a
// time as ranks ask for work, longest expected first: runs differ in length
// by orders of magnitude, so a split fixed in advance would leave ranks idle.
// Rank 0 also runs runs on its own workers, reports progress and writes the
// summary. Every rank writes its runs' result files and outcomes into the
// shared result directory, so resuming an aborted job, shards and --collect
// work from the files exactly as they do on one machine.

#include <string>

#include "engine/app/sweep_runner.hpp"

namespace granflow {

// Initialises and finalises MPI itself; every error is reported once, by the
// rank that saw it (rank 0 where all saw it), and all ranks return rank 0's
// exit status. options.workers: runs at a time per rank (0: the cores the
// rank is bound to, or the machine's cores shared among its ranks).
int run_sweep_on_ranks(const std::string& sweep_file, const std::string& output_directory,
                       const SweepOptions& options);

}  // namespace granflow
