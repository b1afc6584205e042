// libFuzzer target for the configuration and sweep-file loaders: the input
// is a TOML file checked against a schema with every kind of key (integers,
// reals with and without infinity, booleans, choices, strings, lists of
// numbers, lists of tables), its first line doubles as a --set assignment,
// and the same text is read as a sweep file whose fixed keys and parameter
// points are applied to that schema. Any input must end in a result or a
// ConfigError; everything else (a crash, another exception, a sanitizer
// report, a run out of memory) is a finding.
//   tests/fuzz/run_config_fuzz.sh SECONDS

#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/app/sweep_file.hpp"
#include "engine/core/config.hpp"

namespace {

const granflow::ConfigSchema& schema() {
  static const granflow::ConfigSchema s = [] {
    granflow::ConfigSchema wall;
    wall.choice("axis", "y", {"x", "y", "z"}, "axis").real("position", 0.0, 0.0, 1.0, "where");
    granflow::ConfigSchema out;
    out.choice("scenario", "haff_cooling", {"haff_cooling"}, "name")
        .integer("system.count", 1000, 1, 1 << 30, "N")
        .real("system.radius", 0.025, 0.0, 1.0, "r", true)
        .real_or_infinite("run.max_collisions_per_particle", 1e300, 0.0, "limit")
        .boolean("initial.remove_mean_velocity", true, "flag")
        .choice("system.boundary", "periodic", {"periodic", "reflecting"}, "boundary")
        .text("output.label", "", "text")
        .real_array("system.cells", {1, 1, 1}, 1, 1e6, 1, 3, "cells")
        .table_array("walls", std::move(wall), 0, 6, "walls");
    return out;
  }();
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    granflow::Config config = granflow::Config::from_toml_text(schema(), text, "fuzz input");
    (void)config.to_toml();
  } catch (const granflow::ConfigError&) {
  }
  try {
    granflow::Config config(schema());
    config.apply_override(text.substr(0, text.find('\n')));
    granflow::Config::from_toml_text(schema(), config.to_toml(), "round trip");
  } catch (const granflow::ConfigError&) {
  }
  try {
    const granflow::SweepFile sweep = granflow::parse_sweep_text(text, "fuzz input");
    granflow::Config base(schema());
    for (const auto& [key, value] : sweep.fixed) base.apply_override(key + "=" + value);
    for (const auto& point : sweep.points) {
      granflow::Config config = base;
      for (const auto& [key, value] : point) config.apply_override(key + "=" + value);
    }
  } catch (const granflow::ConfigError&) {
  }
  return 0;
}
