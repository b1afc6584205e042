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

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
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
  // exchange_with_neighbours in two halves, so that a rank works while the
  // messages travel: start_exchange sends (`down` and `up` stay as they are
  // until finish_exchange), finish_exchange returns what arrived. Where the
  // ranks cannot overlap the two, start only keeps the messages and finish
  // exchanges them.
  struct Exchange {
    int below = 0, above = 0, channel = 0;
    std::vector<double> down, up;
    std::shared_ptr<void> in_flight;  // the implementation's requests, between the halves
  };
  // finish_exchange waits only for what comes to this rank: the neighbours
  // may still be reading what it sent (a shared-memory transport reads the
  // sender's buffer in place) until they finish too. wait_sent waits for
  // that; call it before `down` or `up` change, so that a rank waits for a
  // late neighbour only there, a step later.
  virtual void start_exchange(Exchange&) const {}
  virtual Received finish_exchange(Exchange& e) const {
    return exchange_with_neighbours(e.below, e.down, e.above, e.up, e.channel);
  }
  virtual void wait_sent(Exchange&) const {}
  // Every rank's `mine`, concatenated in rank order, on every rank.
  virtual std::vector<double> gather_all(const std::vector<double>& mine) const = 0;
  // Every rank's `mine`, concatenated in rank order, on rank 0 only (the
  // others get nothing): what one writer needs, without the whole on every
  // rank.
  virtual std::vector<double> gather_to_first(const std::vector<double>& mine) const {
    std::vector<double> all = gather_all(mine);
    if (rank() != 0) all.clear();
    return all;
  }
  // The same for one column without a copy: every rank's `elements`
  // elements of `width` values at `mine` into `all` on rank 0, which holds
  // room for the total that counts_on_first told it (`all` is not read
  // elsewhere). A column of up to 2^31 elements of any width.
  virtual std::vector<std::int64_t> counts_on_first(std::int64_t mine) const {
    const std::vector<double> all = gather_all({static_cast<double>(mine)});
    std::vector<std::int64_t> counts;
    if (rank() == 0)
      for (const double c : all) counts.push_back(static_cast<std::int64_t>(c));
    return counts;
  }
  virtual void gather_to_first(const double* mine, std::size_t elements, std::size_t width, double* all) const {
    const std::vector<double> gathered = gather_all(std::vector<double>(mine, mine + elements * width));
    if (rank() == 0) std::copy(gathered.begin(), gathered.end(), all);
  }
  virtual std::int64_t sum(std::int64_t value) const = 0;
  // Rank 0's value on every rank.
  virtual bool from_first(bool value) const = 0;
  // Rank 0's values (of any length) on every rank.
  virtual std::vector<double> values_from_first(const std::vector<double>& values) const {
    const std::vector<double> sizes = gather_all({static_cast<double>(values.size())});
    std::vector<double> all = gather_all(values);
    all.resize(static_cast<std::size_t>(sizes.front()));
    return all;
  }
  // sum in two halves, as the exchange: started with this rank's value,
  // read (and waited for) at finish_sum. Other collective calls may come
  // between, in the same order on every rank.
  struct Sum {
    std::int64_t mine = 0, total = 0;
    std::shared_ptr<void> in_flight;
  };
  virtual void start_sum(Sum&) const {}
  virtual std::int64_t finish_sum(Sum& s) const { return sum(s.mine); }

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
  // The element-wise least of every rank's `mine` (all of one length), on
  // every rank (a largest is the least of the negated values).
  std::vector<double> least_across(const std::vector<double>& mine) const {
    std::vector<double> least = mine;
    const std::vector<double> all = gather_all(mine);
    for (std::size_t k = 0; k < all.size() && !mine.empty(); ++k)
      least[k % mine.size()] = std::min(least[k % mine.size()], all[k]);
    return least;
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
    const std::int64_t total = sum(count + (interrupted_here() ? interrupt_flag : 0));
    agree_on_interrupt(total >= interrupt_flag);
    return total % interrupt_flag;
  }
  // The same in two halves: a step that does its work between them waits
  // for the slowest rank only where that one is later than the work.
  void start_agreeing_on_interrupt(Sum& s, std::int64_t count) const {
    s.mine = count + (interrupted_here() ? interrupt_flag : 0);
    start_sum(s);
  }
  std::int64_t finish_agreeing_on_interrupt(Sum& s) const {
    const std::int64_t total = finish_sum(s);
    agree_on_interrupt(total >= interrupt_flag);
    return total % interrupt_flag;
  }
  // For a step that agrees on the signal inside a collective call of its
  // own: this process's flag to send, then whether any rank's was set.
  bool interrupted_here() const { return local_interrupt_ && local_interrupt_->load(); }
  void agree_on_interrupt(bool any) const {
    if (local_interrupt_) agreed_interrupt_.store(any);
  }

 private:
  static constexpr std::int64_t interrupt_flag = std::int64_t{1} << 40;
  const std::atomic<bool>* local_interrupt_ = nullptr;
  mutable std::atomic<bool> agreed_interrupt_{false};
};

}  // namespace granflow
