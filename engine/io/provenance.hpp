#pragma once
// Where a result came from, written to /provenance of every result file
// (and the author to /h5md/author): the build (engine/io/version.hpp), the
// command line, host, user, thread limit, the ranks one system is spread
// over, and the start and end of writing.

#include <string>

namespace granflow {

// Called once by the command-line program; a library user who skips it gets
// an empty command line in the files.
void record_command_line(int argc, const char* const* argv);
const std::string& recorded_command_line();

std::string host_name();
std::string user_name();
// ISO 8601, UTC, to the second.
std::string utc_timestamp();
// The largest number of threads the run may use (the --threads limit).
int thread_limit();
// The number of MPI ranks one system is spread over (`mpirun -np K granflow
// run`): 1 unless the launcher records more.
void record_rank_count(int ranks);
int rank_count();

}  // namespace granflow
