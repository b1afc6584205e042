#include "engine/app/sweep_runner.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <mutex>
#include <optional>

#include "engine/app/sweep_results.hpp"
#include "engine/run/progress.hpp"
#include "engine/run/runner.hpp"
#include "engine/run/scenario.hpp"

namespace granflow {

namespace {

// SHARD_RECORD: one line per run of the shard, its file and its status.
void write_shard_record(const SweepPlan& plan, const Shard& shard, const std::vector<bool>& mine,
                        const std::vector<std::string>& status) {
  std::string text;
  for (std::size_t k = 0; k < plan.runs.size(); ++k)
    if (mine[k]) text += plan.runs[k].output.filename().string() + " " + status[k] + "\n";
  write_text_file(plan.directory / shard_record_name(shard.index, shard.count), text);
}

// The shard counts N of the shard records in the directory.
std::vector<std::size_t> recorded_shard_counts(const SweepPlan& plan) {
  std::vector<std::size_t> counts;
  for (const auto& entry : std::filesystem::directory_iterator(plan.directory)) {
    const std::string name = entry.path().filename().string();
    const auto of = name.find("_of_");
    if (name.rfind("shard_", 0) != 0 || of == std::string::npos || entry.path().extension() != ".txt") continue;
    try {
      const std::size_t n = std::stoul(name.substr(of + 4));
      if (n > 0 && std::find(counts.begin(), counts.end(), n) == counts.end()) counts.push_back(n);
    } catch (const std::exception&) {
    }
  }
  std::sort(counts.begin(), counts.end());
  return counts;
}

// --collect: the summary of what the shards left, and an error naming each
// failed run and each missing one (by shard, where shard records tell N).
int collect_summary(const SweepPlan& plan, const std::vector<std::string>& status) {
  write_summary_of(plan, status);
  std::vector<std::size_t> missing;
  std::size_t not_done = 0;
  for (std::size_t k = 0; k < plan.runs.size(); ++k) {
    if (status[k] == "done") continue;
    ++not_done;
    if (status[k] == "missing") {
      missing.push_back(k);
      continue;
    }
    std::string why;
    recorded_status(plan.runs[k], &why);
    spdlog::error("{}: {}{}", plan.runs[k].output.filename().string(), status[k], why.empty() ? "" : ": " + why);
  }
  const auto names = [&](const std::vector<std::size_t>& runs) {
    std::vector<std::string> out;
    for (const std::size_t k : runs) out.push_back(plan.runs[k].output.filename().string());
    return fmt::format("{}", fmt::join(out, ", "));
  };
  if (!missing.empty()) {
    const auto counts = recorded_shard_counts(plan);
    if (counts.empty()) {
      spdlog::error("{} of {} runs have no result: {}", missing.size(), plan.runs.size(), names(missing));
    } else {
      for (const std::size_t count : counts) {
        const auto shard = shard_of_runs(plan, count);
        for (std::size_t i = 0; i < count; ++i) {
          std::vector<std::size_t> its;
          std::size_t size = 0;
          for (std::size_t k = 0; k < plan.runs.size(); ++k)
            if (shard[k] == i) ++size;
          for (const std::size_t k : missing)
            if (shard[k] == i) its.push_back(k);
          if (its.empty()) continue;
          const std::string record = shard_record_name(i + 1, count);
          const bool ran = std::filesystem::exists(plan.directory / record);
          spdlog::error("shard {}/{} {}: {} of its {} runs have no result: {}", i + 1, count,
                        ran ? "ran but did not finish them" : fmt::format("has not finished (no {})", record),
                        its.size(), size, names(its));
        }
      }
    }
  }
  spdlog::info("sweep collected: {} runs, {} not finished normally ({} without a result); summary in {}",
               plan.runs.size(), not_done, missing.size(), (plan.directory / "summary.csv").string());
  return not_done ? 3 : 0;
}

}  // namespace

SweepWork survey_sweep(const SweepPlan& plan, const SweepOptions& options) {
  if (!scenario_registry().find(plan.scenario)) throw ConfigError(fmt::format("unknown scenario '{}'", plan.scenario));
  std::filesystem::create_directories(plan.directory);
  SweepWork work;
  work.mine.assign(plan.runs.size(), true);
  if (options.shard.count > 0) {
    const auto shard = shard_of_runs(plan, options.shard.count);
    for (std::size_t k = 0; k < plan.runs.size(); ++k) work.mine[k] = shard[k] == options.shard.index - 1;
  }
  work.status.assign(plan.runs.size(), "pending");
  for (std::size_t k = 0; k < plan.runs.size(); ++k) {
    // A shard looks only at its own runs; --collect at every run.
    if (!work.mine[k] && !options.collect) continue;
    if (finished(plan, k))
      work.status[k] = recorded_status(plan.runs[k]).value_or("done");
    else if (options.collect)
      work.status[k] = recorded_status(plan.runs[k]) == "failed" ? "failed" : "missing";
    else if (work.mine[k])
      work.todo.push_back(k);
  }
  // Longest expected first: the last runs to start are then the short ones,
  // which keeps every worker busy until the end.
  std::stable_sort(work.todo.begin(), work.todo.end(),
                   [&](std::size_t a, std::size_t b) { return plan.runs[a].cost > plan.runs[b].cost; });
  work.assigned = static_cast<std::size_t>(std::count(work.mine.begin(), work.mine.end(), true));
  if (options.collect) return work;
  // Names are checked against a result already there, if any (another
  // shard's counts as well).
  for (std::size_t k = 0; k < plan.runs.size() && !work.summary_checked; ++k)
    if ((work.status[k] != "pending" || !work.mine[k]) && std::filesystem::exists(plan.runs[k].output)) {
      check_summary_names(plan, plan.runs[k].output);
      work.summary_checked = true;
    }
  return work;
}

void log_sweep_start(const SweepPlan& plan, const SweepOptions& options, const SweepWork& work,
                     const std::string& workers) {
  const std::string part = options.shard.count ? fmt::format(", shard {}/{}: {} runs", options.shard.index,
                                                             options.shard.count, work.assigned)
                                               : "";
  spdlog::info("sweep of {}: {} parameter points x {} repeats = {} runs{}, {} already done, {}, results in {}",
               plan.scenario, plan.parameter_values.size(), plan.repeats, plan.runs.size(), part,
               work.assigned - work.todo.size(), workers, plan.directory.string());
}

std::string execute_sweep_run(const SweepPlan& plan, std::size_t k, const InterruptGuard* guard) {
  const SweepRun& run = plan.runs[k];
  RunOptions run_options;
  run_options.output_path = run.output.string();
  run_options.progress = false;
  run_options.handle_signals = false;
  run_options.interrupt_guard = guard;
  run_options.resume = std::filesystem::exists(run.output.string() + ".checkpoint");
  std::string outcome, why;
  try {
    // Each run on one thread of its own: the sweep's parallelism is across
    // runs, and a run's passes then take their sequential paths instead of
    // handing work to slots that are busy with other runs.
    int code = 0;
    tbb::task_arena one_thread(1);
    const Config config = plan.run_config(k);
    one_thread.execute([&] { code = run_scenario(*scenario_registry().find(plan.scenario), config, run_options); });
    if (guard && code == exit_interrupted(guard->signal_number())) return "interrupted";
    outcome = code == 0 ? "done" : fmt::format("stopped (exit {})", code);
  } catch (const std::exception& error) {
    outcome = "failed";
    why = error.what();
    spdlog::error("{}: {}", run.output.string(), why);
  }
  record_status(run, outcome, why);
  return outcome;
}

int conclude_sweep(const SweepPlan& plan, const SweepOptions& options, const SweepWork& work) {
  std::size_t failures = 0;
  for (std::size_t k = 0; k < plan.runs.size(); ++k)
    if (work.mine[k] && work.status[k] != "done") ++failures;
  if (options.shard.count > 0) {
    write_shard_record(plan, options.shard, work.mine, work.status);
    spdlog::info("shard {}/{} finished: {} runs, {} newly run, {} not finished normally; `granflow sweep FILE "
                 "--collect` writes the summary once every shard has run",
                 options.shard.index, options.shard.count, work.assigned, work.todo.size(), failures);
    return failures ? 3 : 0;
  }
  write_summary_of(plan, work.status);
  spdlog::info("sweep finished: {} runs, {} newly run, {} not finished normally; summary in {}", plan.runs.size(),
               work.todo.size(), failures, (plan.directory / "summary.csv").string());
  return failures ? 3 : 0;
}

SweepTally::SweepTally(const SweepPlan& plan, SweepWork& work, bool show_progress)
    : plan_(plan), work_(work), progress_("sweep", "runs/s", show_progress) {}

void SweepTally::record(std::size_t run, const std::string& outcome) {
  work_.status[run] = outcome;
  if (!work_.summary_checked && std::filesystem::exists(plan_.runs[run].output)) {
    work_.summary_checked = true;
    try {
      check_summary_names(plan_, plan_.runs[run].output);
    } catch (const ConfigError& error) {
      summary_error_ = error;
      abandoned_ = true;
    }
  }
  ++done_;
  progress_.update(static_cast<double>(done_) / static_cast<double>(work_.todo.size()), static_cast<double>(done_),
                   fmt::format("{}/{} runs done", work_.assigned - work_.todo.size() + done_, work_.assigned));
}

void SweepTally::interrupt() { progress_.finish(); }

void SweepTally::finish() {
  progress_.finish();
  if (summary_error_) throw *summary_error_;
}

int run_sweep(const SweepPlan& plan, const SweepOptions& options) {
  SweepWork work = survey_sweep(plan, options);
  if (options.collect) return collect_summary(plan, work.status);
  const int workers = options.workers > 0 ? options.workers : tbb::this_task_arena::max_concurrency();
  log_sweep_start(plan, options, work, fmt::format("{} workers", workers));

  // Points log only warnings; the sweep reports its own progress.
  const auto level = spdlog::get_level();
  spdlog::set_level(spdlog::level::warn);
  std::mutex report;
  SweepTally tally(plan, work, options.progress);
  // A signal stops the runs under way at their next safe point (each writes
  // its checkpoint) and starts no more; a rerun continues them.
  InterruptGuard guard;
  std::size_t interrupted = 0;
  tbb::task_arena arena(workers);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, work.todo.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t t = range.begin(); t != range.end(); ++t) {
            if (tally.abandoned() || guard.requested()) continue;
            const std::size_t k = work.todo[t];
            const std::string outcome = execute_sweep_run(plan, k, &guard);
            std::lock_guard lock(report);
            if (outcome == "interrupted") ++interrupted;
            else tally.record(k, outcome);
          }
        },
        tbb::simple_partitioner());
  });
  spdlog::set_level(level);
  if (guard.requested()) {
    tally.interrupt();
    spdlog::warn("sweep interrupted (signal {}): {} run(s) under way checkpointed; run the same command to continue",
                 guard.signal_number(), interrupted);
    return exit_interrupted(guard.signal_number());
  }
  tally.finish();
  return conclude_sweep(plan, options, work);
}

}  // namespace granflow
