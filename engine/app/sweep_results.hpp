#pragma once
// What a sweep leaves on disk and reads back: the result files (complete
// only once renamed into place), a one-line outcome beside each
// (RESULT.status: done, stopped (exit N), or failed and why) and the summary
// tables built from them. Whoever ran a run (a worker thread, a shard of a
// job array, an MPI rank), the summary is a function of these files alone.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/app/sweep_plan.hpp"

namespace granflow {

// The run's result file exists and was written with its configuration;
// ConfigError where a file is there but unreadable or from other settings,
// so that results of two sweeps are never mixed.
bool finished(const SweepPlan& plan, std::size_t k);

// Summary names are checked against the first result file at hand, so that a
// misspelt name stops the sweep after one run rather than after all of them.
void check_summary_names(const SweepPlan& plan, const std::filesystem::path& result);

// Written to FILE.partial and renamed: whole or not at all, like the result files.
void write_text_file(const std::filesystem::path& path, const std::string& text);

void record_status(const SweepRun& run, const std::string& outcome, const std::string& why);

// The first line of RESULT.status (the outcome) and, into `why`, the second.
std::optional<std::string> recorded_status(const SweepRun& run, std::string* why = nullptr);

// summary.csv, summary_runs.csv and summary.h5 from the result files at hand;
// status[k] is run k's outcome ("failed" and "missing" runs have no values).
void write_summary_of(const SweepPlan& plan, const std::vector<std::string>& status);

}  // namespace granflow
