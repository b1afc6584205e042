#pragma once
// The ranks one system is spread over (`mpirun -np K granflow run`): what a
// distributed step needs of them, so that systems do not depend on the MPI
// library. engine/app implements it on MPI_COMM_WORLD; a run without ranks
// has none (Run::communicator() is null).
//
// Every call is collective: each rank makes the same calls in the same
// order, or the job hangs. Where a decision depends on something one rank
// sees first (a signal, the wall clock), it is agreed through these calls
// before any rank acts on it.

#include <atomic>
#include <cstdint>
#include <vector>

namespace granflow {

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;

  // Sends `send` to rank `to` and returns what rank `from` sent this rank
  // with the same `channel` (a tag: two channels between one pair of ranks
  // do not mix).
  virtual std::vector<double> exchange(int to, const std::vector<double>& send, int from, int channel) const = 0;
  // Every rank's `mine`, concatenated in rank order, on every rank.
  virtual std::vector<double> gather_all(const std::vector<double>& mine) const = 0;
  virtual std::int64_t sum(std::int64_t value) const = 0;
  virtual double sum(double value) const = 0;
  virtual bool any(bool value) const = 0;
  // Rank 0's value on every rank.
  virtual bool from_first(bool value) const = 0;

  // The signal flag of this process and the one every rank agrees on: a
  // distributed step calls agree_on_interrupt once per step, and the run
  // loop watches the agreed flag, so that all ranks stop at the same step.
  void watch_interrupt(const std::atomic<bool>* local) { local_interrupt_ = local; }
  const std::atomic<bool>* agreed_interrupt() const { return local_interrupt_ ? &agreed_interrupt_ : nullptr; }
  void agree_on_interrupt() const {
    if (local_interrupt_) agreed_interrupt_.store(any(local_interrupt_->load()));
  }

 private:
  const std::atomic<bool>* local_interrupt_ = nullptr;
  mutable std::atomic<bool> agreed_interrupt_{false};
};

}  // namespace granflow
