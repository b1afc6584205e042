#pragma once
// Runs a built-in scenario into a file of the test's scratch directory, as
// `granflow run` would but quietly and without taking over the signals, and
// opens the result. The run's exit status is checked (0).

#include <gtest/gtest.h>

#include <string>

#include "engine/core/config.hpp"
#include "engine/io/h5md_reader.hpp"
#include "engine/run/runner.hpp"
#include "engine/run/scenario.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {

inline H5mdReader run_scenario_in(const ScratchDirectory& scratch, const std::string& scenario, const Config& config,
                                  const std::string& name) {
  RunOptions options;
  options.output_path = (scratch.path / (name + ".h5md")).string();
  options.progress = false;
  options.handle_signals = false;
  EXPECT_EQ(run_scenario(*scenario_registry().find(scenario), config, options), 0) << scenario << " (" << name << ")";
  return H5mdReader(options.output_path);
}

}  // namespace granflow
