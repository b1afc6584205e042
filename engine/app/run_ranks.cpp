#include "engine/app/run_ranks.hpp"

#include <fmt/format.h>
#include <mpi.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <climits>
#include <exception>
#include <stdexcept>

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
    // Sizes first, then the values: a receiver cannot know how many particles cross.
    // Tags tell the downward from the upward messages apart where below == above.
    const int downward = 4 * channel, upward = 4 * channel + 1;
    long long send_down = static_cast<long long>(down.size()), send_up = static_cast<long long>(up.size());
    long long from_above = 0, from_below = 0;
    MPI_Request sizes[4];
    MPI_Irecv(&from_above, 1, MPI_LONG_LONG, above, downward, MPI_COMM_WORLD, &sizes[0]);
    MPI_Irecv(&from_below, 1, MPI_LONG_LONG, below, upward, MPI_COMM_WORLD, &sizes[1]);
    MPI_Isend(&send_down, 1, MPI_LONG_LONG, below, downward, MPI_COMM_WORLD, &sizes[2]);
    MPI_Isend(&send_up, 1, MPI_LONG_LONG, above, upward, MPI_COMM_WORLD, &sizes[3]);
    MPI_Waitall(4, sizes, MPI_STATUSES_IGNORE);
    if (std::max({send_down, send_up, from_above, from_below}) > INT_MAX)
      throw std::runtime_error(fmt::format("more than {} values to exchange between two ranks in one message; use "
                                           "more ranks",
                                           INT_MAX));
    Received received;
    received.from_above.resize(static_cast<std::size_t>(from_above));
    received.from_below.resize(static_cast<std::size_t>(from_below));
    MPI_Request values[4];
    MPI_Irecv(received.from_above.data(), static_cast<int>(from_above), MPI_DOUBLE, above, downward + 2,
              MPI_COMM_WORLD, &values[0]);
    MPI_Irecv(received.from_below.data(), static_cast<int>(from_below), MPI_DOUBLE, below, upward + 2,
              MPI_COMM_WORLD, &values[1]);
    MPI_Isend(down.data(), static_cast<int>(send_down), MPI_DOUBLE, below, downward + 2, MPI_COMM_WORLD, &values[2]);
    MPI_Isend(up.data(), static_cast<int>(send_up), MPI_DOUBLE, above, upward + 2, MPI_COMM_WORLD, &values[3]);
    MPI_Waitall(4, values, MPI_STATUSES_IGNORE);
    return received;
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
