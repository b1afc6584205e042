#include "engine/run/runner.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>

#include "engine/core/interrupt.hpp"
#include "engine/core/profiler.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/io/checkpoint_file.hpp"
#include "engine/io/h5_handle.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/io/h5md_reader.hpp"
#include "engine/run/progress.hpp"
#include "engine/run/run.hpp"
#include "engine/run/thermo_log.hpp"

namespace granflow {

std::uint64_t member_seed(std::int64_t base, std::size_t member) {
  if (member == 0) return static_cast<std::uint64_t>(base);
  // Non-negative, as run.seed requires, so a member's seed can be given back as run.seed.
  return derived_seed(stream::ensemble_seed, static_cast<std::uint64_t>(base), member) >> 1;
}

namespace {

// Fails before any work when the result file cannot be written there.
void check_output_path(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error))
    throw InputError(fmt::format("output '{}' is a directory; give a file name with -o", path));
  const fs::path parent = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(parent, error))
    throw InputError(fmt::format("cannot write output '{}': directory '{}' does not exist", path, parent.string()));
  if (::access(parent.c_str(), W_OK) != 0)
    throw InputError(fmt::format("cannot write output '{}': {}", path, std::strerror(errno)));
  if (fs::exists(path, error) && ::access(path.c_str(), W_OK) != 0)
    throw InputError(fmt::format("cannot replace output '{}': {}", path, std::strerror(errno)));
}

// A fresh run never deletes a checkpoint it did not write: one of another
// configuration stops the run; one of this very configuration (an
// interrupted earlier attempt) is replaced, and that is said.
void check_existing_checkpoint(const std::string& path, const Config& config) {
  if (!std::filesystem::exists(path)) return;
  std::string stored;
  try {
    stored = H5mdReader(path).string_dataset("/parameters/toml");
  } catch (const H5Error&) {
    throw InputError(fmt::format("'{}' exists but is not a readable checkpoint; delete it or choose another -o", path));
  }
  if (stored != config.to_toml())
    throw InputError(fmt::format("checkpoint '{}' of another configuration is in the way; continue it with --resume and "
                                 "its configuration, delete it, or choose another -o",
                                 path));
  spdlog::warn("starting afresh: the checkpoint '{}' of an earlier, unfinished run of this configuration will be "
               "replaced (--resume continues it instead)",
               path);
}

// `exact`: every key but the checkpoint settings must match (an ensemble's
// finished runs were made with them and cannot be extended).
// Over ranks the particle arrays stay in the file, for each rank to read its
// own (Run::initial_state). Rank 0 checks the file whole, reading them
// through in blocks, before the others read what they need.
CheckpointContents read_checkpoint_on(const Communicator* ranks, const std::string& path) {
  if (!ranks || ranks->size() < 2) return read_checkpoint(path);
  std::optional<CheckpointContents> contents;
  std::string refusal;
  if (ranks->rank() == 0) {
    try {
      contents = read_checkpoint(path, {true, true});
    } catch (const InputError& error) {
      refusal = error.what();
    }
  }
  if (!ranks->from_first(refusal.empty())) throw InputError(refusal.empty() ? "--resume: refused on rank 0" : refusal);
  if (ranks->rank() > 0) contents = read_checkpoint(path, {true, false});
  return std::move(*contents);
}

CheckpointContents load_for_resume(const std::string& path, const ConfigSchema& schema, const Config& config,
                                   bool exact = false, const Communicator* ranks = nullptr) {
  if (!std::filesystem::exists(path))
    throw InputError(fmt::format("--resume: there is no checkpoint '{}' to resume from", path));
  CheckpointContents contents = read_checkpoint_on(ranks, path);
  Config stored;
  try {
    stored = Config::from_toml_text(schema, contents.configuration, path);
  } catch (const ConfigError& error) {
    throw InputError(fmt::format("--resume: checkpoint '{}' does not fit this scenario's keys ({})", path, error.what()));
  }
  auto conflicts = config.resume_conflicts(stored);
  if (exact)
    for (const auto& [key, value] : config.values())
      if (key.rfind("output.checkpoint_interval", 0) != 0 && key != "output.final_checkpoint" &&
          stored.values().at(key) != value && std::find(conflicts.begin(), conflicts.end(), key) == conflicts.end())
        conflicts.push_back(key);
  if (!conflicts.empty()) {
    std::string list;
    for (const auto& key : conflicts)
      list += fmt::format("{}{} (checkpoint: {}, now: {})", list.empty() ? "" : ", ", key,
                          stored.values().count(key) ? to_string(stored.values().at(key)) : "-",
                          config.values().count(key) ? to_string(config.values().at(key)) : "-");
    throw InputError(fmt::format("--resume: checkpoint '{}' was written with other values of keys that change the "
                                 "physics or what was already averaged: {}; resume with the same file and --set "
                                 "options, or delete the checkpoint",
                                 path, list));
  }
  return contents;
}

// A checkpoint that reads but holds impossible state (sizes, indices,
// values) is refused with what is wrong, rather than crashing or silently
// continuing from it.
template <class Action>
void refusing_bad_checkpoint(const std::string& path, bool resuming, Action&& action) {
  if (!resuming) return action();
  try {
    action();
  } catch (const std::invalid_argument& error) {
    throw InputError(fmt::format("--resume: checkpoint '{}' is not usable: {}; delete it to start afresh", path,
                                 error.what()));
  } catch (const std::out_of_range& error) {
    throw InputError(fmt::format("--resume: checkpoint '{}' lacks data this run needs ({}); delete it to start afresh",
                                 path, error.what()));
  }
}

std::string output_path_of(const Scenario& scenario, const RunOptions& options) {
  return options.output_path.empty() ? scenario.default_output : options.output_path;
}

void report_interruption(int signal_number, const std::string& checkpoint, const std::string& what) {
  spdlog::warn("interrupted (signal {}) {}; the state is saved in '{}': run the same command with --resume to "
               "continue",
               signal_number, what, checkpoint);
}

int single_run(const Scenario& scenario, const Config& config, const RunOptions& options) {
  const std::string output = output_path_of(scenario, options);
  const std::string checkpoint = output + ".checkpoint";
  // Over several ranks, rank 0 observes and writes the result and the
  // checkpoints; the others run the same loop without a file or observers,
  // and adopt rank 0's observers' decisions (Run::run_observers).
  Communicator* const ranks = options.communicator;
  const bool writer = !ranks || ranks->rank() == 0;
  check_output_path(output);
  std::optional<CheckpointContents> resumed;
  if (options.resume)
    resumed = load_for_resume(checkpoint, config.schema(), config, false, ranks);
  else
    check_existing_checkpoint(checkpoint, config);
  if (writer && std::filesystem::exists(output)) spdlog::info("replacing the existing result file '{}'", output);

  // From here on a signal stops the run at a safe point instead of killing it.
  std::optional<InterruptGuard> own_guard;
  const InterruptGuard* guard = options.interrupt_guard;
  if (!guard && options.handle_signals) guard = &own_guard.emplace();
  if (ranks && guard) ranks->watch_interrupt(&guard->requested());
  const std::atomic<bool>* interrupt = guard ? (ranks ? ranks->agreed_interrupt() : &guard->requested()) : nullptr;
  std::optional<H5mdFile> file;
  if (writer) {
    file.emplace(output, scenario.name);
    file->write_parameters(config);
    if (ranks) file->write_attribute("/parameters/derived", "ranks", static_cast<double>(ranks->size()));
  }
  Profiler profiler;
  Run run(config, profiler, static_cast<std::uint64_t>(config.integer("run.seed")), 0,
          resumed ? &resumed->state : nullptr, file ? &*file : nullptr);
  run.on_ranks(ranks);
  if (resumed) run.resume_rows(&resumed->rows);
  {
    Progress setup(scenario.name + " setup", "", options.progress && writer);
    run.on_setup_progress([&setup](const std::string& phase, double fraction) { setup.update(fraction, 0.0, phase); });
    if (guard) run.on_interrupt(&guard->requested());
    std::optional<std::string> interrupted;
    refusing_bad_checkpoint(checkpoint, resumed.has_value(), [&] {
      try {
        scenario.build(run);
        if (ranks && ranks->size() > 1 && !run.distributed())
          throw ConfigError(fmt::format(
              "{} has no distributed step: it runs one system on one machine, with every core of it as threads "
              "(--threads); start it without mpirun, or spread several runs over ranks with `mpirun -np {} "
              "granflow sweep FILE` (one system over ranks: the SRD scenarios)",
              scenario.name, ranks->size()));
        run.prepare();
      } catch (const PreparationInterrupted& stop) {
        interrupted = stop.what();
      }
    });
    setup.finish();
    run.on_setup_progress({});
    if (interrupted) {
      spdlog::warn("{} (signal {}) while preparing the initial state: nothing to resume", *interrupted,
                   guard->signal_number());
      return exit_interrupted(guard->signal_number());
    }
  }
  if (guard && guard->requested() && !ranks) {
    spdlog::warn("interrupted (signal {}) while preparing the initial state: nothing to resume", guard->signal_number());
    return exit_interrupted(guard->signal_number());
  }
  if (resumed) spdlog::info("resuming from '{}' at t = {:.6g}", checkpoint, run.clock().time);
  if (file) file->flush();  // readable from the start: parameters, and a resumed run's series so far

  Progress progress(scenario.name, run.rate_unit(), options.progress && options.log_every == 0 && writer);
  std::optional<ThermoLog> log;
  if (options.log_every > 0 && writer) log.emplace(options.log_every, options.log_observables, run.recorder());
  const double interval = config.real("output.checkpoint_interval");
  auto last_checkpoint = std::chrono::steady_clock::now();
  // Collective over ranks: every rank takes part. Where the step lends each
  // rank's particles, they are written by rank, never gathered whole.
  const auto write_state = [&](const StateMap& state, const RankRows& rows) {
    if (!rows.arrays.empty())
      write_checkpoint_by_rank(checkpoint, scenario.name, config, state, rows, *ranks);
    else if (writer)
      write_checkpoint(checkpoint, scenario.name, config, state);
  };
  const auto save_checkpoint = [&] {
    RankRows rows;
    const StateMap state = run.save(ranks ? &rows : nullptr);
    write_state(state, rows);
  };
  const auto after_round = [&] {
    progress.update(run.progress_fraction(), run.work_done());
    if (log) log->after_round(run.clock().step, run.clock().time);
    const auto now = std::chrono::steady_clock::now();
    bool due = std::chrono::duration<double>(now - last_checkpoint).count() >= interval;
    if (ranks) due = ranks->from_first(due);  // rank 0's clock decides for all
    if (due) {
      save_checkpoint();
      last_checkpoint = std::chrono::steady_clock::now();
    }
  };
  if (config.boolean("output.final_checkpoint")) run.split_stop_round();
  const RunOutcome outcome = run.execute(interrupt, after_round);
  progress.finish();
  if (outcome.kind == RunOutcome::Kind::interrupted) {
    save_checkpoint();
    // Over ranks the signal may have reached one rank alone (a scheduler's
    // kill of one process): every rank reports the first rank's that did.
    int signal_number = guard->signal_number();
    if (ranks && ranks->size() > 1)
      for (const double received : ranks->gather_all({static_cast<double>(signal_number)}))
        if (received > 0) {
          signal_number = static_cast<int>(received);
          break;
        }
    if (writer) report_interruption(signal_number, checkpoint, fmt::format("at t = {:.6g}", run.clock().time));
    return exit_interrupted(signal_number);
  }
  run.write_results(outcome);
  // Taken while the file is open: the checkpoint carries the frames it holds.
  std::optional<StateMap> final_state;
  RankRows final_rows;
  if (config.boolean("output.final_checkpoint")) final_state = run.save(ranks ? &final_rows : nullptr);
  if (file) {
    file->write_profile(profiler.entries());
    file->finish();
  }
  if (final_state)
    write_state(*final_state, final_rows);
  else if (file)
    std::filesystem::remove(checkpoint);
  if (options.profile && writer) fmt::print("{}", profiler.table());
  if (writer) spdlog::info("wrote {} (t = {:.6g}: {})", output, run.clock().time, outcome.reason);
  if (outcome.kind == RunOutcome::Kind::failed) {
    if (writer) spdlog::error("{}", outcome.reason);
    return exit_physics_failed;
  }
  return exit_finished;
}

EnsembleMember member_record(const Run& run, const RunOutcome& outcome) {
  EnsembleMember member;
  member.history = run.recorder().history();
  for (const auto& [name, value] : run.derived_values()) member.derived[name] = value;
  member.units = run.observable_units();
  member.stop_reason = outcome.reason;
  return member;
}

// Why an ensemble's runs ended: their one reason, or each reason (without
// the time it came at) with the runs, as ranges, that ended for it.
std::string ensemble_stop_reason(const std::vector<std::optional<EnsembleMember>>& members) {
  std::map<std::string, std::vector<std::size_t>> runs_by_reason;
  for (std::size_t r = 0; r < members.size(); ++r) {
    const std::string& reason = members[r]->stop_reason;
    runs_by_reason[reason.substr(0, reason.find(" at t = "))].push_back(r);
  }
  if (runs_by_reason.size() == 1 && members.size() == 1) return members.front()->stop_reason;
  if (runs_by_reason.size() == 1) return runs_by_reason.begin()->first;
  std::vector<std::string> parts;
  for (const auto& [reason, runs] : runs_by_reason) {
    std::vector<std::string> ranges;
    for (std::size_t k = 0; k < runs.size();) {
      std::size_t last = k;
      while (last + 1 < runs.size() && runs[last + 1] == runs[last] + 1) ++last;
      ranges.push_back(last == k ? std::to_string(runs[k]) : fmt::format("{}-{}", runs[k], runs[last]));
      k = last + 1;
    }
    parts.push_back(fmt::format("{} {}: {}", runs.size() == 1 ? "run" : "runs", fmt::join(ranges, ", "), reason));
  }
  return fmt::format("{}", fmt::join(parts, "; "));
}

// Runs every member not yet finished, in parallel: members are independent
// worlds, each a deterministic function of its seed. `done` is called with
// each member's outcome (under no lock), `round` after each of its rounds.
void run_members(const Scenario& scenario, const Config& config, Profiler& profiler,
                 const std::atomic<bool>* interrupt, const std::vector<std::optional<EnsembleMember>>& finished,
                 std::vector<StateMap>& in_progress,
                 const std::function<void(std::size_t, Run&, const RunOutcome&)>& done,
                 const std::function<void(std::size_t, const Run&)>& round) {
  tbb::parallel_for(std::size_t{0}, finished.size(), [&](std::size_t r) {
    if (finished[r] || (interrupt && interrupt->load())) return;
    StateMap from;
    from.swap(in_progress[r]);  // each member touches only its own entry
    Run run(config, profiler, member_seed(config.integer("run.seed"), r), r, from.empty() ? nullptr : &from, nullptr);
    run.on_interrupt(interrupt);
    try {
      scenario.build(run);
    } catch (const PreparationInterrupted&) {
      return;  // this member starts afresh when resumed
    }
    run.prepare();
    const RunOutcome outcome = run.execute(interrupt, [&] {
      if (round) round(r, run);
    });
    done(r, run, outcome);
  });
}

std::string member_prefix(std::size_t member) { return fmt::format("member{}", member); }

int ensemble_run(const Scenario& scenario, const Config& config, const RunOptions& options) {
  const std::string output = output_path_of(scenario, options);
  const std::string checkpoint = output + ".checkpoint";
  check_output_path(output);
  const std::size_t count = scenario.members(config);
  if (count == 0) throw ConfigError(fmt::format("{}: the ensemble has no members", scenario.name));
  // From here on a signal stops the runs at a safe point instead of killing them.
  std::optional<InterruptGuard> own_guard;
  const InterruptGuard* guard = options.interrupt_guard;
  if (!guard && options.handle_signals) guard = &own_guard.emplace();
  std::vector<std::optional<EnsembleMember>> finished(count);
  std::vector<StateMap> in_progress(count);
  if (options.resume) {
    const auto contents = load_for_resume(checkpoint, config.schema(), config, true);
    for (std::size_t r = 0; r < count; ++r) {
      const std::string prefix = member_prefix(r);
      if (contents.state.count(prefix + "/done")) {
        EnsembleMember member;
        member.history = load_history(state_under(contents.state, prefix + "/history"));
        for (const auto& [name, value] : state_under(contents.state, prefix + "/derived"))
          if (value.size() == 1) member.derived[name] = value[0];
        if (const auto reason = contents.state.find(prefix + "/stop_reason"); reason != contents.state.end())
          member.stop_reason = decode_texts(reason->second).at(0);
        if (const auto units = contents.state.find(prefix + "/units"); units != contents.state.end()) {
          const auto pairs = decode_texts(units->second);
          for (std::size_t k = 0; k + 1 < pairs.size(); k += 2) member.units[pairs[k]] = pairs[k + 1];
        }
        finished[r] = std::move(member);
      } else {
        in_progress[r] = state_under(contents.state, prefix + "/run");
      }
    }
    spdlog::info("resuming from '{}': {} of {} runs done", checkpoint,
                 std::count_if(finished.begin(), finished.end(), [](const auto& m) { return m.has_value(); }), count);
  } else {
    check_existing_checkpoint(checkpoint, config);
  }
  if (std::filesystem::exists(output)) spdlog::info("replacing the existing result file '{}'", output);
  H5mdFile file(output, scenario.name);
  file.write_parameters(config);

  const auto save = [&] {
    StateMap state;
    for (std::size_t r = 0; r < count; ++r) {
      const std::string prefix = member_prefix(r);
      if (finished[r]) {
        state[prefix + "/done"] = {1.0};
        put_state_under(state, prefix + "/history", save_history(finished[r]->history));
        for (const auto& [name, value] : finished[r]->derived) state[prefix + "/derived/" + name] = {value};
        state[prefix + "/stop_reason"] = encode_texts({finished[r]->stop_reason});
        std::vector<std::string> units;
        for (const auto& [name, unit] : finished[r]->units) units.insert(units.end(), {name, unit});
        state[prefix + "/units"] = encode_texts(units);
      } else if (!in_progress[r].empty()) {
        put_state_under(state, prefix + "/run", in_progress[r]);
      }
    }
    write_checkpoint(checkpoint, scenario.name, config, state);
  };

  const std::atomic<bool>* interrupt = guard ? &guard->requested() : nullptr;
  Profiler profiler;
  Progress progress(scenario.name, "runs/s", options.progress);
  std::mutex lock;
  std::vector<double> fraction(count, 0.0);
  for (std::size_t r = 0; r < count; ++r)
    if (finished[r]) fraction[r] = 1.0;
  const auto show = [&] {
    double sum = 0.0;
    for (double f : fraction) sum += f;
    progress.update(sum / static_cast<double>(count), sum,
                    fmt::format("{}/{} runs", std::count(fraction.begin(), fraction.end(), 1.0), count));
  };
  std::optional<std::pair<std::size_t, std::string>> failure;
  refusing_bad_checkpoint(checkpoint, options.resume, [&] {
    run_members(scenario, config, profiler, interrupt, finished, in_progress, [&](std::size_t r, Run& run, const RunOutcome& outcome) {
      std::lock_guard hold(lock);
      if (outcome.kind == RunOutcome::Kind::interrupted) {
        in_progress[r] = run.save();
        return;
      }
      if (outcome.kind == RunOutcome::Kind::failed && (!failure || r < failure->first)) failure.emplace(r, outcome.reason);
      finished[r] = member_record(run, outcome);
      fraction[r] = 1.0;
      show();
      if (std::any_of(finished.begin(), finished.end(), [](const auto& m) { return !m; })) save();
    }, [&](std::size_t r, const Run& run) {
      std::lock_guard hold(lock);
      fraction[r] = std::min(run.progress_fraction(), 0.999);
      show();
    });
  });
  progress.finish();
  const auto done = static_cast<std::size_t>(
      std::count_if(finished.begin(), finished.end(), [](const auto& m) { return m.has_value(); }));
  if (interrupt && interrupt->load() && done < count) {
    save();
    report_interruption(guard->signal_number(), checkpoint, fmt::format("with {} of {} runs done", done, count));
    return exit_interrupted(guard->signal_number());
  }
  if (failure) {
    spdlog::error("run {}: {}", failure->first, failure->second);
    file.write_attribute("/observables", "stop_reason", fmt::format("run {}: {}", failure->first, failure->second));
    file.write_profile(profiler.entries());
    file.finish();
    std::filesystem::remove(checkpoint);
    return exit_physics_failed;
  }
  file.write_attribute("/observables", "stop_reason", ensemble_stop_reason(finished));
  EnsembleResults results{config, {}};
  for (auto& member : finished) results.members.push_back(std::move(*member));
  scenario.reduce(results, file);
  file.write_profile(profiler.entries());
  file.finish();
  std::filesystem::remove(checkpoint);
  if (options.profile) fmt::print("{}", profiler.table());
  spdlog::info("wrote {} ({} runs)", output, count);
  return exit_finished;
}

}  // namespace

EnsembleResults simulate_ensemble(const Scenario& scenario, const Config& config) {
  if (!scenario.ensemble()) throw std::logic_error("simulate_ensemble: '" + scenario.name + "' is not an ensemble");
  const std::size_t count = scenario.members(config);
  std::vector<std::optional<EnsembleMember>> finished(count);
  std::vector<StateMap> in_progress(count);
  Profiler profiler;
  std::mutex lock;
  std::optional<std::string> failure;
  run_members(scenario, config, profiler, nullptr, finished, in_progress,
              [&](std::size_t r, Run& run, const RunOutcome& outcome) {
                std::lock_guard hold(lock);
                if (outcome.kind == RunOutcome::Kind::failed) failure = outcome.reason;
                finished[r] = member_record(run, outcome);
              }, {});
  if (failure) throw PhysicsFailure(*failure);
  EnsembleResults results{config, {}};
  for (auto& member : finished) results.members.push_back(std::move(*member));
  return results;
}

int run_scenario(const Scenario& scenario, const Config& given, const RunOptions& options) {
  Config config = given;
  if (scenario.adopt) scenario.adopt(config);
  if (options.communicator && options.communicator->size() > 1 && scenario.runs_as_ensemble(config))
    throw ConfigError(fmt::format("{} with run.runs = {} is an ensemble of independent runs: spread them over ranks "
                                  "with `mpirun -np {} granflow sweep FILE` (one system over ranks needs run.runs = 1)",
                                  scenario.name, config.integer("run.runs"), options.communicator->size()));
  try {
    return scenario.runs_as_ensemble(config) ? ensemble_run(scenario, config, options)
                                             : single_run(scenario, config, options);
  } catch (const H5Error& error) {
    // The usual cause of a failed write: say so where it is so.
    const std::string output = output_path_of(scenario, options);
    const auto directory = std::filesystem::absolute(output).parent_path();
    std::error_code ignored;
    const auto space = std::filesystem::space(directory, ignored);
    if (!ignored && space.available < (1u << 20))
      throw H5Error(fmt::format("{} (the file system of '{}' is full: {} bytes free)", error.what(), output,
                                space.available));
    throw;
  }
}

}  // namespace granflow
