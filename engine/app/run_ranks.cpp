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

  std::vector<double> exchange(int to, const std::vector<double>& send, int from, int channel) const override {
    // Sizes first, then the values: a receiver cannot know how many particles cross.
    long long count = static_cast<long long>(send.size()), incoming = 0;
    MPI_Sendrecv(&count, 1, MPI_LONG_LONG, to, 2 * channel, &incoming, 1, MPI_LONG_LONG, from, 2 * channel,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (count > INT_MAX || incoming > INT_MAX)
      throw std::runtime_error(fmt::format("{} values to exchange between two ranks exceed one MPI message; use more "
                                           "ranks", std::max(count, incoming)));
    std::vector<double> received(static_cast<std::size_t>(incoming));
    MPI_Sendrecv(send.data(), static_cast<int>(count), MPI_DOUBLE, to, 2 * channel + 1, received.data(),
                 static_cast<int>(incoming), MPI_DOUBLE, from, 2 * channel + 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
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
  double sum(double value) const override {
    double out = 0.0;
    MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    return out;
  }
  bool any(bool value) const override {
    int in = value ? 1 : 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return out != 0;
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
