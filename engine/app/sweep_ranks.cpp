#include "engine/app/sweep_ranks.hpp"

#include <fmt/format.h>
#include <mpi.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "engine/app/mpi_session.hpp"
#include "engine/app/sweep_results.hpp"
#include "engine/core/config.hpp"
#include "engine/run/runner.hpp"

namespace granflow {

namespace {

// Worker rank -> rank 0: "RUN OUTCOME WANTS", RUN the run it finished (-1:
// none yet), WANTS 1 when it has a free worker. Rank 0 -> worker rank: the
// run to do next, or -1 when there is none left.
constexpr int tag_report = 1;
constexpr int tag_assign = 2;
constexpr long long no_run = -1;

// Messages are rare (one per run, and runs last seconds to days), so waiting
// ranks poll and sleep rather than spin a core that a run could use.
constexpr auto poll_interval = std::chrono::milliseconds(2);

struct Finished {
  std::size_t run;
  std::string outcome;
};

// The runs handed to this rank, on its own worker threads; only the thread
// that talks to the other ranks calls MPI (it would do with MPI_THREAD_FUNNELED).
class RunSlots {
 public:
  RunSlots(const SweepPlan& plan, int workers) : plan_(plan), workers_(static_cast<std::size_t>(workers)) {
    for (int w = 0; w < workers; ++w) threads_.emplace_back([this] { work(); });
  }
  ~RunSlots() {
    {
      std::lock_guard lock(mutex_);
      closing_ = true;
    }
    work_ready_.notify_all();
    for (auto& thread : threads_) thread.join();
  }
  RunSlots(const RunSlots&) = delete;
  RunSlots& operator=(const RunSlots&) = delete;

  std::size_t busy() const {
    std::lock_guard lock(mutex_);
    return busy_;
  }
  bool has_room() const { return busy() < workers_; }

  void start(std::size_t run) {
    {
      std::lock_guard lock(mutex_);
      queued_.push_back(run);
      ++busy_;
    }
    work_ready_.notify_one();
  }

  // The runs finished since the last call, waiting up to `wait` for one.
  std::vector<Finished> collect(std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    run_done_.wait_for(lock, wait, [&] { return !finished_.empty(); });
    std::vector<Finished> out;
    out.swap(finished_);
    busy_ -= out.size();
    return out;
  }

 private:
  void work() {
    for (;;) {
      std::size_t run = 0;
      {
        std::unique_lock lock(mutex_);
        work_ready_.wait(lock, [&] { return closing_ || !queued_.empty(); });
        if (queued_.empty()) return;
        run = queued_.front();
        queued_.pop_front();
      }
      std::string outcome;
      try {
        outcome = execute_sweep_run(plan_, run);
      } catch (const std::exception& error) {  // its outcome could not be recorded (a full disk)
        spdlog::error("{}: {}", plan_.runs[run].output.string(), error.what());
        outcome = "failed";
      }
      {
        std::lock_guard lock(mutex_);
        finished_.push_back({run, std::move(outcome)});
      }
      run_done_.notify_one();
    }
  }

  const SweepPlan& plan_;
  std::size_t workers_;
  mutable std::mutex mutex_;
  std::condition_variable work_ready_, run_done_;
  std::deque<std::size_t> queued_;
  std::vector<Finished> finished_;
  std::size_t busy_ = 0;  // queued or running
  bool closing_ = false;
  std::vector<std::thread> threads_;
};

void send_report(long long run, const std::string& outcome, bool wants_more) {
  const std::string text = fmt::format("{} {}\n{}", run, wants_more ? 1 : 0, outcome);
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, 0, tag_report, MPI_COMM_WORLD);
}

struct Report {
  int rank;
  long long run;
  bool wants_more;
  std::string outcome;
};

std::optional<Report> receive_report() {
  int waiting = 0;
  MPI_Status status;
  MPI_Iprobe(MPI_ANY_SOURCE, tag_report, MPI_COMM_WORLD, &waiting, &status);
  if (!waiting) return std::nullopt;
  int length = 0;
  MPI_Get_count(&status, MPI_CHAR, &length);
  std::string text(static_cast<std::size_t>(length), '\0');
  MPI_Recv(text.data(), length, MPI_CHAR, status.MPI_SOURCE, tag_report, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  Report report{status.MPI_SOURCE, no_run, false, ""};
  std::istringstream in(text);
  int wants = 0;
  in >> report.run >> wants;
  in.ignore(1);
  std::getline(in, report.outcome);
  report.wants_more = wants != 0;
  return report;
}

long long wait_for_assignment() {
  long long run = no_run;
  MPI_Request request;
  MPI_Irecv(&run, 1, MPI_LONG_LONG, 0, tag_assign, MPI_COMM_WORLD, &request);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return run;
    std::this_thread::sleep_for(poll_interval);
  }
}

// Rank 0: hands out work.todo in order to its own workers and to the ranks
// that ask, records the outcomes, and returns once every run handed out has
// come back and every rank has been told that nothing is left.
void deal_runs(const SweepPlan& plan, SweepWork& work, int ranks, int workers, bool show_progress) {
  RunSlots slots(plan, workers);
  SweepTally tally(plan, work, show_progress);
  std::size_t next = 0;
  std::vector<std::size_t> outstanding(static_cast<std::size_t>(ranks), 0);
  std::vector<bool> released(static_cast<std::size_t>(ranks), false);
  released[0] = true;
  const auto take = [&]() -> long long {
    if (tally.abandoned() || next == work.todo.size()) return no_run;
    return static_cast<long long>(work.todo[next++]);
  };
  for (;;) {
    while (slots.has_room()) {
      const long long run = take();
      if (run == no_run) break;
      slots.start(static_cast<std::size_t>(run));
    }
    while (const auto report = receive_report()) {
      const auto rank = static_cast<std::size_t>(report->rank);
      if (report->run != no_run) {
        --outstanding[rank];
        tally.record(static_cast<std::size_t>(report->run), report->outcome);
      }
      if (report->wants_more) {
        const long long run = take();
        MPI_Send(&run, 1, MPI_LONG_LONG, report->rank, tag_assign, MPI_COMM_WORLD);
        if (run == no_run)
          released[rank] = true;
        else
          ++outstanding[rank];
      }
    }
    for (const auto& finished : slots.collect(poll_interval)) tally.record(finished.run, finished.outcome);
    const bool nothing_left = tally.abandoned() || next == work.todo.size();
    bool ranks_done = true;
    for (int r = 0; r < ranks; ++r) ranks_done = ranks_done && released[r] && outstanding[r] == 0;
    if (nothing_left && ranks_done && slots.busy() == 0) break;
  }
  tally.finish();
}

// Ranks other than 0: ask for a run whenever a worker is free, report each
// finished run, stop asking once rank 0 has none left.
void serve_runs(const SweepPlan& plan, int workers) {
  RunSlots slots(plan, workers);
  bool released = false;
  while (!released && slots.has_room()) {
    send_report(no_run, "", true);
    const long long run = wait_for_assignment();
    if (run == no_run)
      released = true;
    else
      slots.start(static_cast<std::size_t>(run));
  }
  while (slots.busy() > 0) {
    for (const auto& finished : slots.collect(std::chrono::milliseconds(50))) {
      send_report(static_cast<long long>(finished.run), finished.outcome, !released);
      if (released) continue;
      const long long run = wait_for_assignment();
      if (run == no_run)
        released = true;
      else
        slots.start(static_cast<std::size_t>(run));
    }
  }
}

// Runs at a time on this rank: as asked, else the cores the launcher bound
// it to, else the machine's cores shared among the ranks on it.
int workers_of_rank(int asked) {
  if (asked > 0) return asked;
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int on_node = 1;
  MPI_Comm_size(node, &on_node);
  MPI_Comm_free(&node);
  const int usable = tbb::this_task_arena::max_concurrency();
  const auto machine = static_cast<int>(std::thread::hardware_concurrency());
  if (usable < machine) return usable;
  return std::max(1, usable / on_node);
}

// Every rank's status, and whether rank `rank` should report its own error:
// rank 0 always, the others only where rank 0 saw none (then the problem is
// theirs alone, e.g. a file another node cannot read).
int agree(int code, int rank, int ranks, const std::string& message) {
  std::vector<int> codes(static_cast<std::size_t>(ranks), 0);
  MPI_Allgather(&code, 1, MPI_INT, codes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  if (code != 0 && (rank == 0 || codes[0] == 0)) spdlog::error("{}", message);
  int worst = 0;
  for (const int c : codes) worst = std::max(worst, c);
  return worst;
}

int exit_code_of(const std::exception& error) {
  if (dynamic_cast<const InputError*>(&error) || dynamic_cast<const std::invalid_argument*>(&error))
    return exit_bad_input;
  return 1;
}

// Runs `work` on rank 0 alone, reporting what it throws there, and gives
// every rank rank 0's exit status.
template <class Work>
int on_rank_zero(int rank, Work&& work) {
  int code = 0;
  if (rank == 0) {
    try {
      code = work();
    } catch (const std::exception& error) {
      code = exit_code_of(error);
      spdlog::error("{}", error.what());
    }
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return code;
}

// One number that differs when two ranks read different sweeps (a file
// edited between nodes' reads, or another version on another node).
unsigned long long plan_fingerprint(const SweepPlan& plan) {
  // Combined piece by piece: a million runs need no text of them all.
  std::size_t hash = std::hash<std::string>{}(plan.directory.string());
  const auto mix = [&](std::size_t piece) { hash ^= piece + 0x9e3779b97f4a7c15ull + (hash << 6) + (hash >> 2); };
  for (const auto& config : plan.point_configs) mix(std::hash<std::string>{}(config.to_toml()));
  for (const auto& run : plan.runs) {
    mix(std::hash<std::string>{}(run.output.string()));
    mix(static_cast<std::size_t>(run.seed));
  }
  return hash;
}


}  // namespace

int run_sweep_on_ranks(const std::string& sweep_file, const std::string& output_directory,
                       const SweepOptions& options) {
  const MpiSession session;
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (rank > 0) spdlog::set_pattern(fmt::format("[%Y-%m-%d %H:%M:%S.%e] [rank {}] [%^%l%$] %v", rank));

  SweepPlan plan;
  int code = 0;
  std::string message;
  try {
    plan = read_sweep_plan(sweep_file, output_directory);
  } catch (const std::exception& error) {
    code = exit_code_of(error);
    message = error.what();
  }
  if (const int worst = agree(code, rank, ranks, message); worst != 0) return worst;
  unsigned long long fingerprint = plan_fingerprint(plan), first = fingerprint;
  MPI_Bcast(&first, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  const bool same = first == fingerprint;
  if (const int worst = agree(same ? 0 : exit_bad_input, rank, ranks,
                              fmt::format("{} read on this rank gives another sweep than on rank 0 (the file or "
                                          "the scenario file differs between the nodes)",
                                          sweep_file));
      worst != 0)
    return worst;

  // --collect runs nothing: rank 0 alone reads the files.
  if (options.collect) return on_rank_zero(rank, [&] { return run_sweep(plan, options); });

  const int workers = workers_of_rank(options.workers);
  // A run's own parallel parts stay within the rank's share of the cores.
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(workers));
  std::vector<int> all_workers(static_cast<std::size_t>(ranks), 0);
  MPI_Gather(&workers, 1, MPI_INT, all_workers.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);

  SweepWork work;
  code = on_rank_zero(rank, [&] {
    work = survey_sweep(plan, options);
    return 0;
  });
  if (code != 0) return code;

  const auto level = spdlog::get_level();
  if (rank == 0) {
    int total = 0;
    for (const int w : all_workers) total += w;
    log_sweep_start(plan, options, work, fmt::format("{} ranks with {} workers in all", ranks, total));
    spdlog::set_level(std::max(level, spdlog::level::warn));
    try {
      deal_runs(plan, work, ranks, workers, options.progress);
      spdlog::set_level(level);
      code = conclude_sweep(plan, options, work);
    } catch (const ConfigError& error) {
      // A misspelt summary name: every rank has stopped asking for work.
      spdlog::set_level(level);
      spdlog::error("{}", error.what());
      code = exit_bad_input;
    } catch (const std::exception& error) {
      spdlog::error("{}", error.what());
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
  } else {
    spdlog::set_level(std::max(level, spdlog::level::warn));
    try {
      serve_runs(plan, workers);
    } catch (const std::exception& error) {
      spdlog::error("{}", error.what());
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
    spdlog::set_level(level);
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return code;
}

}  // namespace granflow
