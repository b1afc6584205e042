#include "engine/sweep_runner.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>

#include "engine/h5_handle.hpp"
#include "engine/h5md_file.hpp"
#include "engine/h5md_reader.hpp"
#include "engine/progress.hpp"
#include "engine/sample_statistics.hpp"
#include "engine/runner.hpp"
#include "engine/scenario.hpp"

namespace granflow {

namespace {

// A result file counts as finished when it exists (files are renamed into
// place only when complete) and was written with this run's configuration.
bool finished(const SweepRun& run) {
  if (!std::filesystem::exists(run.output)) return false;
  std::string stored;
  try {
    stored = H5mdReader(run.output.string()).string_dataset("/parameters/toml");
  } catch (const H5Error&) {
    throw ConfigError(fmt::format("{} exists but is not a readable result file; delete it to rerun that point",
                                  run.output.string()));
  }
  if (stored != run.config.to_toml())
    throw ConfigError(fmt::format("{} was written with a different configuration than this sweep asks for; delete "
                                  "it or choose another output directory",
                                  run.output.string()));
  return true;
}

// Scalar observables of a result file: /observables/NAME/value series with
// one value per time, component k of a vector series as NAME[k], and numeric
// attributes of /observables.
std::vector<std::string> scalar_observables(const H5mdReader& reader) {
  std::vector<std::string> names;
  if (!reader.exists("/observables")) return names;
  for (const auto& name : reader.members("/observables")) {
    const std::string dataset = "/observables/" + name + "/value";
    if (!reader.exists(dataset)) continue;
    const auto shape = reader.doubles(dataset).shape;
    if (shape.size() <= 1) {
      names.push_back(name);
    } else if (shape.size() == 2) {
      for (std::uint64_t k = 0; k < shape[1]; ++k) names.push_back(fmt::format("{}[{}]", name, k));
    }
  }
  for (const auto& name : reader.attribute_names("/observables")) {
    try {
      (void)reader.double_attribute("/observables", name);
      names.push_back(name);
    } catch (const H5Error&) {  // a text attribute (the stop reason)
    }
  }
  return names;
}

// "NAME[k]": the series NAME and component k; plain names have no component.
std::pair<std::string, std::optional<std::size_t>> split_component(const std::string& name) {
  const auto open = name.find('[');
  if (open == std::string::npos || name.back() != ']') return {name, std::nullopt};
  return {name.substr(0, open), static_cast<std::size_t>(std::stoul(name.substr(open + 1)))};
}

// Summary names are checked against the first result file at hand, so that a
// misspelt name stops the sweep after one run rather than after all of them.
void check_summary_names(const SweepPlan& plan, const std::filesystem::path& result) {
  const H5mdReader reader(result.string());
  const auto available = scalar_observables(reader);
  for (const auto& name : plan.summary) {
    if (std::find(available.begin(), available.end(), name) != available.end()) continue;
    throw ConfigError(fmt::format("summary observable '{}' is not a scalar observable of {} ({}); its scalar "
                                  "observables are: {}. Finished runs are kept: fix `summary` and rerun",
                                  name, plan.scenario, result.string(), fmt::join(available, ", ")));
  }
}

// Last value of a scalar observable (or of one component, NAME[k]), or the
// attribute of that name on /observables; NaN (with a warning) where this
// run's file lacks it.
double summary_value(const H5mdReader& reader, const std::string& name, const std::string& path) {
  const auto [series, component] = split_component(name);
  const std::string dataset = "/observables/" + series + "/value";
  try {
    if (reader.exists(dataset)) {
      const auto array = reader.doubles(dataset);
      if (array.values.empty()) return std::nan("");
      if (!component) return array.values.back();
      const std::size_t width = array.shape.size() == 2 ? array.shape[1] : 1;
      if (*component >= width) return std::nan("");
      return array.values[array.values.size() - width + *component];
    }
    return reader.double_attribute("/observables", name);
  } catch (const H5Error& error) {
    spdlog::warn("{}: summary observable '{}' not readable ({}); its entry is NaN", path, name, error.what());
    return std::nan("");
  }
}

// The unit of a summary observable as its result file gives it ("" if none).
std::string summary_unit(const H5mdReader& reader, const std::string& name) {
  const std::string dataset = "/observables/" + split_component(name).first + "/value";
  try {
    if (reader.exists(dataset)) return reader.string_attribute(dataset, "unit");
  } catch (const H5Error&) {
  }
  return "";
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string number_text(double value) { return std::isfinite(value) ? fmt::format("{:.17g}", value) : "nan"; }

struct Column {
  std::string name;
  std::vector<std::string> texts;  // text columns
  std::vector<double> numbers;     // numeric columns
};

// Written to FILE.partial and renamed: whole or not at all, like the result files.
void write_text_file(const std::filesystem::path& path, const std::string& text) {
  const auto partial = path.string() + ".partial";
  {
    std::ofstream out(partial);
    out << text;
    if (!out.flush()) throw std::runtime_error("cannot write " + partial);
  }
  std::filesystem::rename(partial, path);
}

void write_csv(const std::filesystem::path& path, const std::vector<Column>& columns) {
  std::ostringstream out;
  for (std::size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << csv_field(columns[c].name);
  out << '\n';
  const std::size_t rows = columns.empty() ? 0
                           : columns.front().texts.empty() ? columns.front().numbers.size()
                                                           : columns.front().texts.size();
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c)
      out << (c ? "," : "")
          << (columns[c].texts.empty() ? number_text(columns[c].numbers[r]) : csv_field(columns[c].texts[r]));
    out << '\n';
  }
  write_text_file(path, out.str());
}

void write_h5_group(H5mdFile& file, const std::string& group, const std::vector<Column>& columns) {
  for (const auto& column : columns) {
    if (column.texts.empty())
      file.write_array(group, column.name, column.numbers);
    else
      file.write_text_array(group, column.name, column.texts);
  }
}

void write_summary(const SweepPlan& plan, const std::vector<std::vector<double>>& values,
                   const std::vector<std::string>& summary_units,
                   const std::vector<std::string>& status, const std::vector<std::string>& stop_reason) {
  const std::size_t points = plan.parameter_values.size();
  // Per run.
  std::vector<Column> runs{{"point", {}, {}}, {"repeat", {}, {}}, {"seed", {}, {}}, {"file", {}, {}},
                           {"status", {}, {}}, {"stop_reason", {}, {}}};
  constexpr std::size_t fixed_columns = 6;
  for (const auto& key : plan.swept_keys) runs.push_back({key, {}, {}});
  for (const auto& name : plan.summary) runs.push_back({name, {}, {}});
  for (std::size_t k = 0; k < plan.runs.size(); ++k) {
    const auto& run = plan.runs[k];
    runs[0].numbers.push_back(static_cast<double>(run.parameter_point));
    runs[1].numbers.push_back(static_cast<double>(run.repeat));
    runs[2].texts.push_back(std::to_string(run.seed));
    runs[3].texts.push_back(run.output.filename().string());
    runs[4].texts.push_back(status[k]);
    runs[5].texts.push_back(stop_reason[k]);
    for (std::size_t s = 0; s < plan.swept_keys.size(); ++s)
      runs[fixed_columns + s].texts.push_back(plan.parameter_values[run.parameter_point][s]);
    for (std::size_t o = 0; o < plan.summary.size(); ++o)
      runs[fixed_columns + plan.swept_keys.size() + o].numbers.push_back(values[k][o]);
  }
  // Per parameter point: mean and standard error of the mean over repeats.
  std::vector<Column> summary{{"point", {}, {}}, {"runs", {}, {}}};
  for (const auto& key : plan.swept_keys) summary.push_back({key, {}, {}});
  for (const auto& name : plan.summary) {
    summary.push_back({name + "_mean", {}, {}});
    summary.push_back({name + "_stderr", {}, {}});
  }
  for (std::size_t p = 0; p < points; ++p) {
    summary[0].numbers.push_back(static_cast<double>(p));
    std::size_t counted = 0;
    for (std::size_t k = 0; k < plan.runs.size(); ++k)
      if (plan.runs[k].parameter_point == p && status[k] != "failed") ++counted;
    summary[1].numbers.push_back(static_cast<double>(counted));
    for (std::size_t s = 0; s < plan.swept_keys.size(); ++s) summary[2 + s].texts.push_back(plan.parameter_values[p][s]);
    for (std::size_t o = 0; o < plan.summary.size(); ++o) {
      std::vector<double> samples;
      for (std::size_t k = 0; k < plan.runs.size(); ++k)
        if (plan.runs[k].parameter_point == p && std::isfinite(values[k][o])) samples.push_back(values[k][o]);
      const auto [mean, error] = mean_and_standard_error(samples);
      summary[2 + plan.swept_keys.size() + 2 * o].numbers.push_back(mean);
      summary[3 + plan.swept_keys.size() + 2 * o].numbers.push_back(error);
    }
  }
  write_csv(plan.directory / "summary.csv", summary);
  write_csv(plan.directory / "summary_runs.csv", runs);
  H5mdFile file((plan.directory / "summary.h5").string(), "sweep");
  file.write_attribute("/parameters", "swept_scenario", plan.scenario);
  file.write_attribute("/parameters", "scenario_file", plan.scenario_file.string());
  file.write_attribute("/parameters", "repeats", static_cast<double>(plan.repeats));
  file.write_text_array("/parameters", "swept_keys", plan.swept_keys);
  // HDF5 lists datasets by name: the order of `summary` and the units are kept beside them.
  file.write_text_array("/parameters", "summary", plan.summary);
  file.write_text_array("/parameters", "summary_units", summary_units);
  std::vector<std::string> key_units;
  const ConfigSchema& schema = scenario_registry().schema(plan.scenario);
  for (const auto& key : plan.swept_keys) key_units.push_back(schema.find(key) ? schema.find(key)->unit : "");
  file.write_text_array("/parameters", "swept_key_units", key_units);
  write_h5_group(file, "/summary", summary);
  write_h5_group(file, "/runs", runs);
  file.finish();
}


// RESULT.status: the outcome of a run's last attempt, and why it failed.
std::filesystem::path status_path(const SweepRun& run) { return run.output.string() + ".status"; }

void record_status(const SweepRun& run, const std::string& outcome, const std::string& why) {
  std::string reason = why;
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  write_text_file(status_path(run), outcome + "\n" + reason + "\n");
}

// The first line of RESULT.status (the outcome), and the second (why it failed).
std::optional<std::string> recorded_status(const SweepRun& run, std::string* why = nullptr) {
  std::ifstream in(status_path(run));
  std::string outcome;
  if (!in || !std::getline(in, outcome) || outcome.empty()) return std::nullopt;
  if (why) std::getline(in, *why);
  return outcome;
}

// The summary tables from the result files at hand and the runs' status.
void write_summary_of(const SweepPlan& plan, const std::vector<std::string>& status) {
  std::vector<std::vector<double>> values(plan.runs.size(),
                                          std::vector<double>(plan.summary.size(), std::nan("")));
  std::vector<std::string> stop_reason(plan.runs.size());
  std::vector<std::string> units;
  for (std::size_t k = 0; k < plan.runs.size(); ++k) {
    if (status[k] == "failed" || status[k] == "missing" || !std::filesystem::exists(plan.runs[k].output)) continue;
    const H5mdReader reader(plan.runs[k].output.string());
    if (units.empty())
      for (const auto& name : plan.summary) units.push_back(summary_unit(reader, name));
    try {
      stop_reason[k] = reader.string_attribute("/observables", "stop_reason");
    } catch (const H5Error&) {
    }
    for (std::size_t o = 0; o < plan.summary.size(); ++o)
      values[k][o] = summary_value(reader, plan.summary[o], plan.runs[k].output.string());
  }
  units.resize(plan.summary.size());
  write_summary(plan, values, units, status, stop_reason);
}

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

int run_sweep(const SweepPlan& plan, const SweepOptions& options) {
  const Scenario* scenario = scenario_registry().find(plan.scenario);
  if (!scenario) throw ConfigError(fmt::format("unknown scenario '{}'", plan.scenario));
  std::filesystem::create_directories(plan.directory);

  // The runs this invocation is about: all, or one shard's.
  std::vector<bool> mine(plan.runs.size(), true);
  if (options.shard.count > 0) {
    const auto shard = shard_of_runs(plan, options.shard.count);
    for (std::size_t k = 0; k < plan.runs.size(); ++k) mine[k] = shard[k] == options.shard.index - 1;
  }
  std::vector<std::string> status(plan.runs.size(), "pending");
  std::vector<std::size_t> todo;
  for (std::size_t k = 0; k < plan.runs.size(); ++k) {
    if (finished(plan.runs[k]))
      status[k] = recorded_status(plan.runs[k]).value_or("done");
    else if (options.collect)
      status[k] = recorded_status(plan.runs[k]) == "failed" ? "failed" : "missing";
    else if (mine[k])
      todo.push_back(k);
  }
  if (options.collect) return collect_summary(plan, status);

  const std::size_t assigned = static_cast<std::size_t>(std::count(mine.begin(), mine.end(), true));
  // Names are checked against a result already there, if any (another
  // shard's counts as well).
  bool summary_checked = false;
  for (std::size_t k = 0; k < plan.runs.size() && !summary_checked; ++k)
    if (status[k] != "pending" && std::filesystem::exists(plan.runs[k].output)) {
      check_summary_names(plan, plan.runs[k].output);
      summary_checked = true;
    }
  const int workers = options.workers > 0 ? options.workers : tbb::this_task_arena::max_concurrency();
  const std::string part =
      options.shard.count ? fmt::format(", shard {}/{}: {} runs", options.shard.index, options.shard.count, assigned)
                          : "";
  spdlog::info("sweep of {}: {} parameter points x {} repeats = {} runs{}, {} already done, {} workers, results in {}",
               plan.scenario, plan.parameter_values.size(), plan.repeats, plan.runs.size(), part,
               assigned - todo.size(), workers, plan.directory.string());

  // Points log only warnings; the sweep reports its own progress.
  const auto level = spdlog::get_level();
  spdlog::set_level(spdlog::level::warn);
  std::mutex report;
  std::atomic<std::size_t> done{0};
  std::atomic<bool> abandoned{false};
  std::optional<ConfigError> summary_error;
  Progress progress("sweep", "runs/s", options.progress);
  tbb::task_arena arena(workers);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, todo.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t t = range.begin(); t != range.end(); ++t) {
            const std::size_t k = todo[t];
            if (abandoned) continue;
            RunOptions run_options;
            run_options.output_path = plan.runs[k].output.string();
            run_options.progress = false;
            run_options.handle_signals = false;
            std::string outcome, why;
            try {
              const int code = run_scenario(*scenario, plan.runs[k].config, run_options);
              outcome = code == 0 ? "done" : fmt::format("stopped (exit {})", code);
            } catch (const std::exception& error) {
              outcome = "failed";
              why = error.what();
              std::lock_guard lock(report);
              spdlog::error("{}: {}", plan.runs[k].output.string(), why);
            }
            record_status(plan.runs[k], outcome, why);
            std::lock_guard lock(report);
            status[k] = outcome;
            if (!summary_checked && std::filesystem::exists(plan.runs[k].output)) {
              summary_checked = true;
              try {
                check_summary_names(plan, plan.runs[k].output);
              } catch (const ConfigError& error) {
                summary_error = error;
                abandoned = true;
              }
            }
            const std::size_t finished_runs = ++done;
            progress.update(static_cast<double>(finished_runs) / static_cast<double>(todo.size()),
                            static_cast<double>(finished_runs),
                            fmt::format("{}/{} runs done", assigned - todo.size() + finished_runs, assigned));
          }
        },
        tbb::simple_partitioner());
  });
  progress.finish();
  spdlog::set_level(level);
  if (summary_error) throw *summary_error;

  std::size_t failures = 0;
  for (std::size_t k = 0; k < plan.runs.size(); ++k)
    if (mine[k] && status[k] != "done") ++failures;
  if (options.shard.count > 0) {
    write_shard_record(plan, options.shard, mine, status);
    spdlog::info("shard {}/{} finished: {} runs, {} newly run, {} not finished normally; `granflow sweep FILE "
                 "--collect` writes the summary once every shard has run",
                 options.shard.index, options.shard.count, assigned, todo.size(), failures);
    return failures ? 3 : 0;
  }
  write_summary_of(plan, status);
  spdlog::info("sweep finished: {} runs, {} newly run, {} not finished normally; summary in {}", plan.runs.size(),
               todo.size(), failures, (plan.directory / "summary.csv").string());
  return failures ? 3 : 0;
}

}  // namespace granflow
