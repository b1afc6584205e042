#pragma once
// What a sweep file says (docs/sweeps.md), read as text and not yet resolved
// against its scenario: which scenario file, where results go, how many
// repeats, which summary observables, the keys fixed for every point and
// the parameter points ([grid] x [zip] x [[points]]). Kept apart from the
// scenarios so the loader can be checked, and fuzzed, on its own.

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/config.hpp"

namespace granflow {

// Keys and values as written (value text as a --set would take it), in file order.
using Assignment = std::vector<std::pair<std::string, std::string>>;

struct SweepFile {
  std::string scenario_file;  // as written, relative to the sweep file
  std::optional<std::string> output;
  std::size_t repeats = 1;
  std::vector<std::string> summary;
  std::vector<std::string> cost;    // keys whose product estimates a run's cost (shards)
  Assignment fixed;                 // [set]
  std::vector<Assignment> points;   // at least one (possibly empty) point
};

// A sweep beyond this many parameter points is refused before it is built
// (a [grid] of a few long lists multiplies quickly).
inline constexpr std::size_t max_sweep_points = 100'000;

// The refusal of a sweep file: "sweep file FILE: WHAT".
ConfigError sweep_file_error(const std::string& file, const std::string& what);

// Throws ConfigError naming `name` and the problem.
SweepFile parse_sweep_text(const std::string& text, const std::string& name);
SweepFile read_sweep_file(const std::string& path);

}  // namespace granflow
