#include "engine/app/cli.hpp"

#include <filesystem>
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>

#include "engine/app/mpi_launch.hpp"
#include "engine/app/run_ranks.hpp"
#include "engine/app/sweep_plan.hpp"
#include "engine/app/sweep_ranks.hpp"
#include "engine/app/sweep_runner.hpp"
#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "engine/core/suggestion.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/io/file_seal.hpp"
#include "engine/io/gsd_export.hpp"
#include "engine/io/h5_handle.hpp"
#include "engine/io/h5md_reader.hpp"
#include "engine/io/mdanalysis_export.hpp"
#include "engine/io/provenance.hpp"
#include "engine/io/version.hpp"
#include "engine/io/xdmf_export.hpp"
#include "engine/io/xyz_export.hpp"
#include "engine/run/runner.hpp"
#include "engine/run/scenario.hpp"

namespace granflow {

namespace {

std::vector<std::string> scenario_names() {
  std::vector<std::string> names;
  for (const auto* s : scenario_registry().all()) names.push_back(s->name);
  return names;
}

// Where the scenario files that come with granflow are: ./scenarios, then
// beside the program (share/granflow/scenarios of an installation, or the
// source tree's scenarios/ for a build inside it).
std::vector<std::filesystem::path> shipped_scenario_directories() {
  std::vector<std::filesystem::path> places{"scenarios"};
  std::error_code error;
  const auto program = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    places.push_back(program.parent_path() / ".." / "share" / "granflow" / "scenarios");
    places.push_back(program.parent_path() / ".." / "scenarios");
  }
  return places;
}

// A configuration file, or the name of a shipped one (`granflow run haff_cooling`).
std::string scenario_file(const std::string& argument) {
  namespace fs = std::filesystem;
  if (fs::exists(argument)) return argument;
  const bool bare_name = argument.find('/') == std::string::npos && fs::path(argument).extension() != ".toml";
  const std::string stem = fs::path(argument).stem().string();
  if (bare_name)
    for (const auto& place : shipped_scenario_directories())
      if (fs::exists(place / (argument + ".toml"))) return (place / (argument + ".toml")).lexically_normal().string();
  std::vector<std::string> shipped;
  for (const auto& place : shipped_scenario_directories())
    if (fs::is_directory(place))
      for (const auto& entry : fs::directory_iterator(place))
        if (entry.path().extension() == ".toml") shipped.push_back(entry.path().stem().string());
  std::sort(shipped.begin(), shipped.end());
  shipped.erase(std::unique(shipped.begin(), shipped.end()), shipped.end());
  if (const auto close = closest_name(stem, shipped))
    throw ConfigError(fmt::format("configuration file '{}' does not exist; did you mean the shipped scenario '{}'?",
                                  argument, *close));
  throw ConfigError(fmt::format("configuration file '{}' does not exist{}", argument,
                                bare_name ? " (nor a shipped scenario of that name: `granflow list` lists them)" : ""));
}

const Scenario& scenario_of_file(const std::string& file) {
  const std::string name = scenario_name_of(file);
  const Scenario* scenario = scenario_registry().find(name);
  if (!scenario)
    throw ConfigError(fmt::format("unknown scenario '{}' in {}{}", name, file, suggestion_text(name, scenario_names(), "scenarios")));
  return *scenario;
}

int run_command(const std::string& argument, const std::vector<std::string>& overrides, const RunOptions& options,
                int threads) {
  const std::string file = scenario_file(argument);
  const Scenario& scenario = scenario_of_file(file);
  const std::string& name = scenario.name;
  Config config = Config::from_file(scenario_registry().schema(name), file);
  for (const auto& assignment : overrides) config.apply_override(assignment);
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  return run_scenario(scenario, config, options);
}

void list_command() {
  fmt::print("scenarios:\n");
  for (const auto* s : scenario_registry().all()) fmt::print("  {:<28} {}\n", s->name, s->summary);
  fmt::print("systems:\n");
  for (const auto& [name, summary] : system_catalogue()) fmt::print("  {:<33} {}\n", name, summary);
}

// A scenario's keys with their defaults, or, given a configuration file (or
// a shipped scenario's name), with the values that file sets.
void keys_command(const std::string& argument) {
  std::string name = argument;
  std::optional<Config> file_values;
  const bool is_file = std::filesystem::exists(argument) || std::filesystem::path(argument).extension() == ".toml";
  if (is_file || !scenario_registry().find(argument)) {
    if (!is_file && argument.find('/') == std::string::npos && !std::filesystem::exists(argument)) {
      bool shipped = false;
      for (const auto& place : shipped_scenario_directories()) shipped |= std::filesystem::exists(place / (argument + ".toml"));
      if (!shipped)
        throw ConfigError(fmt::format("unknown scenario '{}'{}", argument, suggestion_text(argument, scenario_names(), "scenarios")));
    }
    const std::string file = scenario_file(argument);
    name = scenario_of_file(file).name;
    file_values = Config::from_file(scenario_registry().schema(name), file);
    fmt::print("# {} ({}): the file's values; keys it leaves out have their defaults\n", file, name);
  }
  for (const auto& spec : scenario_registry().schema(name).keys()) {
    const ConfigValue& value = file_values ? file_values->values().at(spec.key) : spec.default_value;
    const std::string differs =
        file_values && to_string(value) != to_string(spec.default_value) ? " (default " + to_string(spec.default_value) + ")" : "";
    fmt::print("{:<40} = {:<22} # {}{}; {}{}\n", spec.key, to_string(value), spec.help,
               spec.unit.empty() || spec.unit == "1" ? "" : " [" + spec.unit + "]", spec.allowed(), differs);
  }
}

void require_result_file(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("result file '{}' does not exist", path));
}

void describe_result_file(const std::string& path) {
  const H5mdReader reader(path);
  fmt::print("{}\n", path);
  if (reader.exists("/h5md/creator"))
    fmt::print("  created by {} {}\n", reader.string_attribute("/h5md/creator", "name"),
               reader.string_attribute("/h5md/creator", "version"));
  if (reader.exists("/parameters")) {
    fmt::print("  scenario: {}\n", reader.string_attribute("/parameters", "scenario"));
    if (reader.exists("/parameters/run")) fmt::print("  seed: {}\n", reader.integer_attribute("/parameters/run", "seed"));
  }
  if (reader.exists("/observables"))
    try {
      fmt::print("  stop: {}\n", reader.string_attribute("/observables", "stop_reason"));
    } catch (const H5Error&) {
    }
  // Scalar results, derived parameters and provenance live in attributes.
  for (const auto& [group, title] : {std::pair{"/observables", "results"}, {"/parameters/derived", "derived parameters"},
                                     {"/provenance", "provenance"}}) {
    if (!reader.exists(group)) continue;
    const auto names = reader.attribute_names(group);
    if (names.empty()) continue;
    fmt::print("{} ({} attributes):\n", title, group);
    for (const auto& name : names) fmt::print("  {:<40} {}\n", name, reader.attribute_text(group, name));
  }
  fmt::print("datasets:\n{}", reader.describe());
  if (reader.exists("/parameters/toml")) fmt::print("configuration:\n{}", reader.string_dataset("/parameters/toml"));
}

// A file that cannot be read as a result file is bad input, whatever is wrong with it.
void info_command(const std::string& path, bool edited) {
  require_result_file(path);
  if (const SealState seal = check_seal(path); seal == SealState::broken && !edited)
    throw InputError(fmt::format("'{}' {} (its seal does not match its contents); if you edited it on purpose, "
                                 "run `granflow info --edited {}`",
                                 path, describe(seal), path));
  try {
    describe_result_file(path);
  } catch (const H5Error& error) {
    throw InputError(fmt::format("cannot describe '{}': {}", path, error.what()));
  }
}

void export_command(const std::string& path, const std::string& format, std::string output, bool edited) {
  require_result_file(path);
  if (const SealState seal = check_seal(path); seal == SealState::broken && !edited)
    throw InputError(fmt::format("'{}' {} (its seal does not match its contents)", path, describe(seal)));
  if (output.empty())
    output = std::filesystem::path(path).replace_extension(format == "mdanalysis" ? "mda.h5md" : format).string();
  try {
    const std::size_t frames = format == "xyz"    ? export_extended_xyz(path, output)
                               : format == "gsd" ? export_gsd(path, output)
                               : format == "xdmf" ? export_xdmf(path, output)
                                                  : export_mdanalysis(path, output);
    spdlog::info("{} frames of '{}' written to '{}'", frames, path, output);
  } catch (const H5Error& error) {
    throw InputError(fmt::format("cannot export '{}': {}", path, error.what()));
  }
}

}  // namespace

int main(int argc, char** argv) {
  link_builtin_scenarios();
  record_command_line(argc, argv);
  // Messages go to standard error; standard output carries only what was asked for (tables, lists).
  if (!spdlog::get("granflow")) spdlog::set_default_logger(spdlog::stderr_color_mt("granflow"));
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");
  CLI::App app{"granflow: simulation of granular gases and flows"};
  app.set_version_flag("--version", version_text());
  app.require_subcommand(1);

  std::string file;
  std::vector<std::string> overrides;
  RunOptions options;
  int threads = 0;
  bool quiet = false;
  auto* run = app.add_subcommand("run", "run a scenario from a TOML file");
  run->add_option("file", file, "scenario configuration (.toml), or the name of a shipped one (haff_cooling)")
      ->required();
  run->add_option("--set", overrides, "override a key: section.key=value (repeatable)");
  run->add_option("-o,--output", options.output_path, "output file (H5MD)");
  run->add_option("--threads", threads, "worker threads (default: all cores)")->check(CLI::Range(1, 4096));
  run->add_flag("--profile", options.profile, "print per-system timings (always stored under /profile)");
  run->add_option("--log", options.log_every,
                  "print a table of observables to standard error every N outputs, as the run goes (instead of the "
                  "progress line)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{1000000000}));
  run->add_option("--log-observables", options.log_observables,
                  "the scalar observables --log prints (comma-separated; default: the first six by name)")
      ->delimiter(',');
  run->add_flag("-q,--quiet", quiet, "no progress or info messages");
  run->add_flag("--resume", options.resume,
                "continue from OUTPUT.checkpoint: an interrupted run, or a finished one with a later stop "
                "(keys that change the physics must match)");

  std::string sweep_file;
  std::string sweep_output;
  SweepOptions sweep_options;
  auto* sweep = app.add_subcommand("sweep", "run a parameter sweep or ensemble from a sweep file on all cores");
  sweep->add_option("file", sweep_file, "sweep description (.toml, see docs/sweeps.md)")->required();
  sweep->add_option("-j,--jobs,--threads", sweep_options.workers,
                    "runs at a time (default: all cores; under mpirun, per rank: the cores it is bound to)")
      ->check(CLI::Range(1, 4096));
  sweep->add_option("-o,--output", sweep_output, "result directory (default: the file's `output`)");
  std::string shard_text;
  sweep->add_option("--shard", shard_text,
                    "run only the I-th of N disjoint parts of the sweep (I/N, e.g. a job array's task index); "
                    "no summary: --collect writes it");
  sweep->add_flag("--collect", sweep_options.collect,
                  "run nothing: write the summary from the result files of all shards and name the runs missing "
                  "or failed");
  sweep->add_flag("-q,--quiet", quiet, "no progress or info messages");

  auto* list = app.add_subcommand("list", "list scenarios and systems");
  std::string info_path;
  auto* info = app.add_subcommand("info", "describe a result file");
  info->add_option("file", info_path, "H5MD result file")->required();
  bool edited = false;
  info->add_flag("--edited", edited, "the file was changed after granflow wrote it, on purpose: read it anyway");
  auto* export_frames = app.add_subcommand("export", "write a result file's particle frames for ASE and OVITO "
                                                   "(extended XYZ), HOOMD-blue, gsd and OVITO (GSD), ParaView "
                                                   "(XDMF, with the fields) or MDAnalysis (H5MD)");
  std::string export_path, export_format, export_output;
  export_frames->add_option("file", export_path, "H5MD result file with particle frames")->required();
  export_frames->add_option("--format", export_format,
                            "xyz (extended XYZ), gsd (HOOMD schema), xdmf (XML and OUTPUT.h5 of virtual datasets "
                            "over the result file) or mdanalysis (H5MD linking to the result file, with the series "
                            "at the frames' times)")
      ->required()
      ->check(CLI::IsMember({"xyz", "gsd", "xdmf", "mdanalysis"}));
  export_frames->add_option("-o,--output", export_output,
                            "output file (default: the result's name with .xyz, .gsd, .xdmf or .mda.h5md)");
  export_frames->add_flag("--edited", edited, "the file was changed after granflow wrote it, on purpose: read it anyway");

  std::string keys_name;
  auto* keys = app.add_subcommand("keys", "list a scenario's configuration keys with defaults (or a file's values) "
                                          "and ranges");
  keys->add_option("scenario", keys_name, "scenario name, or a configuration file (.toml) to show its values")
      ->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);
    return code == 0 ? 0 : exit_bad_input;
  }

  try {
    if (*run) {
      // Several ranks spread one system (the scenarios with a distributed
      // step); a build without MPI would run it once per rank into one file.
      if (const int ranks = mpi_world_size_from_environment(); ranks > 1) {
#ifdef GRANFLOW_WITH_MPI
        if (quiet) spdlog::set_level(spdlog::level::warn);
        options.progress = !quiet;
        return run_on_ranks(options, [&](const RunOptions& on_ranks) {
          return run_command(file, overrides, on_ranks, threads);
        });
#else
        if (mpi_rank_from_environment() != 0) return exit_bad_input;
        throw ConfigError(fmt::format(
            "granflow run was started as {} MPI ranks, but this build has no MPI (configure with "
            "-DGRANFLOW_MPI=ON to spread one SRD system over ranks); start it without mpirun to run it on this "
            "machine's cores (--threads)",
            ranks));
#endif
      }
      if (quiet) spdlog::set_level(spdlog::level::warn);
      options.progress = !quiet;
      return run_command(file, overrides, options, threads);
    }
    if (*sweep) {
      if (quiet) spdlog::set_level(spdlog::level::warn);
      sweep_options.progress = !quiet;
      if (!shard_text.empty()) {
        if (sweep_options.collect)
          throw ConfigError("--shard and --collect go in separate calls: each shard runs its part, then one "
                            "--collect writes the summary");
        sweep_options.shard = parse_shard(shard_text);
      }
      const int ranks = mpi_world_size_from_environment();
#ifdef GRANFLOW_WITH_MPI
      if (ranks > 0) return run_sweep_on_ranks(sweep_file, sweep_output, sweep_options);
#else
      if (ranks > 1)
        throw ConfigError(fmt::format("granflow sweep was started as {} MPI ranks, but this granflow was built "
                                      "without MPI, so every rank would run the whole sweep; build it with "
                                      "-DGRANFLOW_MPI=ON, or split the sweep with --shard I/N",
                                      ranks));
#endif
      return run_sweep(read_sweep_plan(sweep_file, sweep_output), sweep_options);
    }
    if (*list) list_command();
    if (*info) info_command(info_path, edited);
    if (*keys) keys_command(keys_name);
    if (*export_frames) export_command(export_path, export_format, export_output, edited);
    return 0;
  } catch (const InputError& error) {
    spdlog::error("{}", error.what());
    return exit_bad_input;
  } catch (const PhysicsFailure& error) {
    spdlog::error("{}", error.what());
    return exit_physics_failed;
  } catch (const std::invalid_argument& error) {
    spdlog::error("{}", error.what());
    return exit_bad_input;
  } catch (const H5Error& error) {
    spdlog::error("{}", error.what());
    return 1;
  } catch (const std::exception& error) {
    spdlog::error("{}", error.what());
    return 1;
  }
}

}  // namespace granflow
