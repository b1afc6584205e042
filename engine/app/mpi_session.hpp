#pragma once
// MPI for the lifetime of one command (a sweep or a run over ranks). The
// calls come from any thread, one at a time: a distributed step runs in
// whichever thread the schedule gives it.

#include <mpi.h>

#include <stdexcept>

namespace granflow {

class MpiSession {
 public:
  MpiSession() {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    if (provided < MPI_THREAD_SERIALIZED)
      throw std::runtime_error("the MPI library offers no calls from several threads (MPI_THREAD_SERIALIZED)");
  }
  ~MpiSession() { MPI_Finalize(); }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

}  // namespace granflow
