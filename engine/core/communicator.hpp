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
#include <cstddef>
#include <cstdint>
#include <vector>

namespace granflow {

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;

  // What crossed between a rank and its two neighbours on a ring of ranks.
  struct Received {
    std::vector<double> from_below, from_above;
  };
  // Sends `down` to rank `below` and `up` to rank `above`, both at once, and
  // returns what they sent this rank: `below`'s up and `above`'s down (they
  // may be one rank). `channel` keeps separate exchanges apart.
  virtual Received exchange_with_neighbours(int below, const std::vector<double>& down, int above,
                                            const std::vector<double>& up, int channel) const = 0;
  // Every rank's `mine`, concatenated in rank order, on every rank.
  virtual std::vector<double> gather_all(const std::vector<double>& mine) const = 0;
  virtual std::int64_t sum(std::int64_t value) const = 0;
  // Rank 0's value on every rank.
  virtual bool from_first(bool value) const = 0;

  // The element-wise sum of every rank's `mine` (all of one length), added
  // in rank order: the same bits on every rank and for every run on this
  // many ranks, whatever order the MPI library would reduce in.
  std::vector<double> add_across(const std::vector<double>& mine) const {
    const std::vector<double> all = gather_all(mine);
    std::vector<double> total(mine.size(), 0.0);
    for (std::size_t r = 0; r + mine.size() <= all.size() && !mine.empty(); r += mine.size())
      for (std::size_t k = 0; k < mine.size(); ++k) total[k] += all[r + k];
    return total;
  }

  // The signal flag of this process and the one every rank agrees on: a
  // distributed step agrees on it once per step (sum_agreeing_on_interrupt),
  // and the run loop watches the agreed flag, so that all ranks stop at the
  // same step.
  void watch_interrupt(const std::atomic<bool>* local) { local_interrupt_ = local; }
  const std::atomic<bool>* agreed_interrupt() const { return local_interrupt_ ? &agreed_interrupt_ : nullptr; }
  // sum(count) (count < 2^40 on every rank), agreeing on the interrupt in
  // the same call: a step that sums something anyway needs no second one.
  std::int64_t sum_agreeing_on_interrupt(std::int64_t count) const {
    constexpr std::int64_t flag = std::int64_t{1} << 40;
    const std::int64_t total = sum(count + (interrupted_here() ? flag : 0));
    agree_on_interrupt(total >= flag);
    return total % flag;
  }
  // For a step that agrees on the signal inside a collective call of its
  // own: this process's flag to send, then whether any rank's was set.
  bool interrupted_here() const { return local_interrupt_ && local_interrupt_->load(); }
  void agree_on_interrupt(bool any) const {
    if (local_interrupt_) agreed_interrupt_.store(any);
  }

 private:
  const std::atomic<bool>* local_interrupt_ = nullptr;
  mutable std::atomic<bool> agreed_interrupt_{false};
};

}  // namespace granflow
