#pragma once
// One system spread over the ranks of an MPI job (`mpirun -np K granflow
// run FILE`, built with -DGRANFLOW_MPI=ON): MPI for the command, the
// Communicator the distributed step talks through, and one exit status for
// all ranks. Errors of the input are the same on every rank and are
// reported by rank 0 alone; an error only one rank meets stops the job.

#include <functional>

#include "engine/run/runner.hpp"

namespace granflow {

// `run` is called on every rank with options that carry the communicator.
int run_on_ranks(RunOptions options, const std::function<int(const RunOptions&)>& run);

}  // namespace granflow
