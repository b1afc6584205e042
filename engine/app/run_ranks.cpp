#include "engine/app/run_ranks.hpp"

#include <fmt/format.h>
#include <mpi.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <climits>
#include <exception>
#include <memory>
#include <stdexcept>
#include <vector>

#include "engine/app/mpi_session.hpp"
#include "engine/core/input_error.hpp"
#include "engine/io/provenance.hpp"

namespace granflow {

namespace {

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  Received exchange_with_neighbours(int below, const std::vector<double>& down, int above,
                                    const std::vector<double>& up, int channel) const override {
    ExchangeRequests requests;
    post(requests, below, down, above, up, channel);
    Received received = complete(requests, below, above, channel);
    requests.wait_sent();
    return received;
  }
  void start_exchange(Exchange& e) const override {
    auto requests = std::make_shared<ExchangeRequests>();
    post(*requests, e.below, e.down, e.above, e.up, e.channel);
    e.in_flight = std::move(requests);
  }
  Received finish_exchange(Exchange& e) const override {
    return complete(*static_cast<ExchangeRequests*>(e.in_flight.get()), e.below, e.above, e.channel);
  }
  void wait_sent(Exchange& e) const override {
    if (!e.in_flight) return;
    static_cast<ExchangeRequests*>(e.in_flight.get())->wait_sent();
    e.in_flight.reset();
  }

  // An exchange's sizes and values go out at once; a receiver learns from
  // the sizes how much to receive. Tags tell the downward from the upward
  // messages apart where below == above. Open MPI's shared-memory transport
  // moves a large message when the receiver posts for it, so a sender that
  // works between post and complete need not be in an MPI call meanwhile.
  struct ExchangeRequests {
    long long send_down = 0, send_up = 0, from_above = 0, from_below = 0;
    MPI_Request sizes[4], sends[2] = {MPI_REQUEST_NULL, MPI_REQUEST_NULL};
    ExchangeRequests() = default;
    ExchangeRequests(const ExchangeRequests&) = delete;
    ExchangeRequests& operator=(const ExchangeRequests&) = delete;
    void wait_sent() { MPI_Waitall(2, sends, MPI_STATUSES_IGNORE); }
    // A run that ends between finish and wait_sent: the receivers have the
    // messages by then; the requests are let go, not waited for.
    ~ExchangeRequests() {
      for (MPI_Request& send : sends)
        if (send != MPI_REQUEST_NULL) MPI_Request_free(&send);
    }
  };
  static void post(ExchangeRequests& r, int below, const std::vector<double>& down, int above,
                   const std::vector<double>& up, int channel) {
    const int downward = 4 * channel, upward = 4 * channel + 1;
    r.send_down = static_cast<long long>(down.size());
    r.send_up = static_cast<long long>(up.size());
    refuse_beyond_int(std::max(r.send_down, r.send_up));
    MPI_Irecv(&r.from_above, 1, MPI_LONG_LONG, above, downward, MPI_COMM_WORLD, &r.sizes[0]);
    MPI_Irecv(&r.from_below, 1, MPI_LONG_LONG, below, upward, MPI_COMM_WORLD, &r.sizes[1]);
    MPI_Isend(&r.send_down, 1, MPI_LONG_LONG, below, downward, MPI_COMM_WORLD, &r.sizes[2]);
    MPI_Isend(&r.send_up, 1, MPI_LONG_LONG, above, upward, MPI_COMM_WORLD, &r.sizes[3]);
    MPI_Isend(down.data(), static_cast<int>(r.send_down), MPI_DOUBLE, below, downward + 2, MPI_COMM_WORLD,
              &r.sends[0]);
    MPI_Isend(up.data(), static_cast<int>(r.send_up), MPI_DOUBLE, above, upward + 2, MPI_COMM_WORLD, &r.sends[1]);
  }
  static Received complete(ExchangeRequests& r, int below, int above, int channel) {
    const int downward = 4 * channel, upward = 4 * channel + 1;
    MPI_Waitall(4, r.sizes, MPI_STATUSES_IGNORE);
    refuse_beyond_int(std::max(r.from_above, r.from_below));
    Received received;
    received.from_above.resize(static_cast<std::size_t>(r.from_above));
    received.from_below.resize(static_cast<std::size_t>(r.from_below));
    MPI_Request values[2];
    MPI_Irecv(received.from_above.data(), static_cast<int>(r.from_above), MPI_DOUBLE, above, downward + 2,
              MPI_COMM_WORLD, &values[0]);
    MPI_Irecv(received.from_below.data(), static_cast<int>(r.from_below), MPI_DOUBLE, below, upward + 2,
              MPI_COMM_WORLD, &values[1]);
    MPI_Waitall(2, values, MPI_STATUSES_IGNORE);
    return received;
  }
  static void refuse_beyond_int(long long values) {
    if (values > INT_MAX)
      throw std::runtime_error(fmt::format("more than {} values to exchange between two ranks in one message; use "
                                           "more ranks",
                                           INT_MAX));
  }

  // A sum in two halves as point-to-point messages of one value to every
  // other rank, not MPI_Iallreduce: Open MPI moves a nonblocking collective
  // on only inside MPI calls, so a rank busy between start and finish would
  // hold the others' finish until its own, while these small messages are
  // delivered at once. K - 1 messages a rank: meant for the few neighbours
  // of a slab step.
  struct SumRequests {
    long long mine = 0;
    std::vector<long long> theirs;
    std::vector<MPI_Request> requests;
  };
  static constexpr int sum_tag = 32000;
  void start_sum(Sum& s) const override {
    auto r = std::make_shared<SumRequests>();
    r->mine = s.mine;
    r->theirs.assign(static_cast<std::size_t>(size_), 0);
    r->requests.assign(2 * static_cast<std::size_t>(size_), MPI_REQUEST_NULL);
    for (int other = 0; other < size_; ++other) {
      if (other == rank_) continue;
      const auto k = static_cast<std::size_t>(other);
      MPI_Irecv(&r->theirs[k], 1, MPI_LONG_LONG, other, sum_tag, MPI_COMM_WORLD, &r->requests[2 * k]);
      MPI_Isend(&r->mine, 1, MPI_LONG_LONG, other, sum_tag, MPI_COMM_WORLD, &r->requests[2 * k + 1]);
    }
    s.in_flight = std::move(r);
  }
  std::int64_t finish_sum(Sum& s) const override {
    auto& r = *static_cast<SumRequests*>(s.in_flight.get());
    MPI_Waitall(static_cast<int>(r.requests.size()), r.requests.data(), MPI_STATUSES_IGNORE);
    r.theirs[static_cast<std::size_t>(rank_)] = r.mine;
    s.total = 0;
    for (const long long value : r.theirs) s.total += value;
    s.in_flight.reset();
    return s.total;
  }

  std::vector<double> gather_all(const std::vector<double>& mine) const override {
    const long long count = static_cast<long long>(mine.size());
    std::vector<long long> counts(static_cast<std::size_t>(size_));
    MPI_Allgather(&count, 1, MPI_LONG_LONG, counts.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD);
    long long total = 0;
    std::vector<int> sizes, offsets;
    for (const long long c : counts) {
      offsets.push_back(static_cast<int>(total));
      sizes.push_back(static_cast<int>(c));
      total += c;
    }
    if (total > INT_MAX)
      throw std::runtime_error(fmt::format("gathering {} values exceeds one MPI message: the state is too large to "
                                           "gather for output on every rank",
                                           total));
    std::vector<double> all(static_cast<std::size_t>(total));
    MPI_Allgatherv(mine.data(), static_cast<int>(count), MPI_DOUBLE, all.data(), sizes.data(), offsets.data(),
                   MPI_DOUBLE, MPI_COMM_WORLD);
    return all;
  }

  std::vector<double> gather_to_first(const std::vector<double>& mine) const override {
    const Layout layout = layout_on_first(static_cast<std::int64_t>(mine.size()));
    std::vector<double> all(layout.total);
    gather_elements(mine.data(), mine.size(), 1, all.data(), layout);
    return all;
  }
  std::vector<std::int64_t> counts_on_first(std::int64_t mine) const override {
    long long count = mine;
    std::vector<long long> counts(rank_ == 0 ? static_cast<std::size_t>(size_) : 0);
    MPI_Gather(&count, 1, MPI_LONG_LONG, counts.data(), 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    return {counts.begin(), counts.end()};
  }
  void gather_to_first(const double* mine, std::size_t elements, std::size_t width, double* all) const override {
    gather_elements(mine, elements, width, all, layout_on_first(static_cast<std::int64_t>(elements)));
  }

  // Where rank 0 receives each rank's elements. MPI counts them in ints:
  // every rank learns whether the total fits, so that all refuse together.
  struct Layout {
    std::vector<int> sizes, offsets;
    std::size_t total = 0;
  };
  Layout layout_on_first(std::int64_t elements) const {
    Layout layout;
    std::int64_t total = 0;
    for (const std::int64_t count : counts_on_first(elements)) {
      layout.offsets.push_back(static_cast<int>(std::min<std::int64_t>(total, INT_MAX)));
      layout.sizes.push_back(static_cast<int>(count));
      total += count;
    }
    int fits = total <= INT_MAX ? 1 : 0;
    MPI_Bcast(&fits, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!fits) throw std::runtime_error("more than 2^31 elements to gather for output on rank 0");
    layout.total = static_cast<std::size_t>(total);
    return layout;
  }
  // One element is `width` doubles (an MPI type of its own), so that the
  // counts and offsets count elements, not values.
  static void gather_elements(const double* mine, std::size_t elements, std::size_t width, double* all,
                              const Layout& layout) {
    MPI_Datatype element;
    MPI_Type_contiguous(static_cast<int>(width), MPI_DOUBLE, &element);
    MPI_Type_commit(&element);
    MPI_Gatherv(mine, static_cast<int>(elements), element, all, layout.sizes.data(), layout.offsets.data(), element,
                0, MPI_COMM_WORLD);
    MPI_Type_free(&element);
  }

  std::vector<double> values_from_first(const std::vector<double>& values) const override {
    long long count = static_cast<long long>(values.size());
    MPI_Bcast(&count, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    refuse_beyond_int(count);
    std::vector<double> out = rank_ == 0 ? values : std::vector<double>(static_cast<std::size_t>(count));
    MPI_Bcast(out.data(), static_cast<int>(count), MPI_DOUBLE, 0, MPI_COMM_WORLD);
    return out;
  }

  std::int64_t sum(std::int64_t value) const override {
    long long in = value, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    return out;
  }
  bool from_first(bool value) const override {
    int flag = value ? 1 : 0;
    MPI_Bcast(&flag, 1, MPI_INT, 0, MPI_COMM_WORLD);
    return flag != 0;
  }

 private:
  int rank_ = 0;
  int size_ = 1;
};

}  // namespace

int run_on_ranks(RunOptions options, const std::function<int(const RunOptions&)>& run) {
  const MpiSession session;
  MpiCommunicator ranks;
  options.communicator = &ranks;
  record_rank_count(ranks.size());
  const auto level = spdlog::get_level();
  // What every rank would say, rank 0 says.
  if (ranks.rank() > 0) spdlog::set_level(spdlog::level::err);
  int code = 0;
  try {
    code = run(options);
  } catch (const InputError& error) {
    // The same input on every rank: the same refusal everywhere, said once.
    if (ranks.rank() == 0) spdlog::error("{}", error.what());
    code = 2;
  } catch (const std::exception& error) {
    // Met by this rank alone, perhaps while the others wait for it.
    spdlog::error("rank {}: {}", ranks.rank(), error.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  spdlog::set_level(level);
  return code;
}

}  // namespace granflow
