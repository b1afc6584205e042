#pragma once
// Whether this process was started by an MPI launcher (mpirun, mpiexec, srun
// with PMI), read from the environment the launcher sets, so that a plain
// `granflow sweep` never initialises MPI and a build without MPI can refuse
// to run the same sweep once per rank.

#include <cstdlib>
#include <string>

namespace granflow {

// The number of ranks the launcher started, 0 when not started by one.
inline int mpi_world_size_from_environment() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
    const char* value = std::getenv(name);
    if (!value) continue;
    try {
      const int size = std::stoi(value);
      if (size > 0) return size;
    } catch (const std::exception&) {
    }
  }
  return std::getenv("PMIX_RANK") ? 1 : 0;
}

// This process's rank among them (0 when not started by a launcher).
inline int mpi_rank_from_environment() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"}) {
    const char* value = std::getenv(name);
    if (!value) continue;
    try {
      return std::stoi(value);
    } catch (const std::exception&) {
    }
  }
  return 0;
}

}  // namespace granflow
