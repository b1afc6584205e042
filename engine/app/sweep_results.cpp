#include "engine/app/sweep_results.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "engine/core/sample_statistics.hpp"
#include "engine/io/h5_handle.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/io/h5md_reader.hpp"
#include "engine/run/scenario.hpp"

namespace granflow {

namespace {



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

}  // namespace

bool finished(const SweepPlan& plan, std::size_t k) {
  const SweepRun& run = plan.runs[k];
  if (!std::filesystem::exists(run.output)) return false;
  std::string stored;
  try {
    stored = H5mdReader(run.output.string()).string_dataset("/parameters/toml");
  } catch (const H5Error&) {
    throw ConfigError(fmt::format("{} exists but is not a readable result file; delete it to rerun that point",
                                  run.output.string()));
  }
  if (stored != plan.run_config(k).to_toml())
    throw ConfigError(fmt::format("{} was written with a different configuration than this sweep asks for; delete "
                                  "it or choose another output directory",
                                  run.output.string()));
  return true;
}

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

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  const auto partial = path.string() + ".partial";
  {
    std::ofstream out(partial);
    out << text;
    if (!out.flush()) throw std::runtime_error("cannot write " + partial);
  }
  std::filesystem::rename(partial, path);
}

void record_status(const SweepRun& run, const std::string& outcome, const std::string& why) {
  std::string reason = why;
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  write_text_file(status_path(run), outcome + "\n" + reason + "\n");
}

std::optional<std::string> recorded_status(const SweepRun& run, std::string* why) {
  std::ifstream in(status_path(run));
  std::string outcome;
  if (!in || !std::getline(in, outcome) || outcome.empty()) return std::nullopt;
  if (why) std::getline(in, *why);
  return outcome;
}

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

}  // namespace granflow
