// A checkpoint gives back the exact state and configuration it was written
// with, and one that was damaged after writing is refused by name.

#include "engine/io/checkpoint_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

ConfigSchema schema() {
  ConfigSchema s;
  s.integer("system.count", 10, 1, 1000, "particles").real("run.t_stop", 1.0, 0.0, 1e9, "stop");
  return s;
}

TEST(CheckpointFile, StateAndConfigurationComeBackExactly) {
  ScratchDirectory scratch("granflow_checkpoint_test_");
  const std::string path = (scratch.path / "run.checkpoint").string();
  const ConfigSchema s = schema();
  const Config config = Config::from_toml_text(s, "[system]\ncount = 42\n", "test");
  const StateMap state{{"gas/time", {0.1 + 0.2}},
                       {"gas/velocities", {1e-300, -0.0, std::numeric_limits<double>::max(), 3.0}},
                       {"empty", {}},
                       {"counter", {9007199254740992.0}}};  // 2^53, exact in a double
  write_checkpoint(path, "io_test", config, state);
  const CheckpointContents back = read_checkpoint(path);
  ASSERT_EQ(back.state.size(), state.size());
  for (const auto& [name, values] : state) {
    ASSERT_EQ(back.state.at(name).size(), values.size()) << name;
    for (std::size_t k = 0; k < values.size(); ++k) {
      EXPECT_EQ(back.state.at(name)[k], values[k]) << name << "[" << k << "]";
      EXPECT_EQ(std::signbit(back.state.at(name)[k]), std::signbit(values[k])) << name << "[" << k << "]";
    }
  }
  const Config again = Config::from_toml_text(s, back.configuration, "checkpoint");
  EXPECT_EQ(again.integer("system.count"), 42);
}

TEST(CheckpointFile, ADamagedOrMissingFileIsRefusedByName) {
  ScratchDirectory scratch("granflow_checkpoint_test_");
  const std::string path = (scratch.path / "damaged.checkpoint").string();
  const ConfigSchema s = schema();
  write_checkpoint(path, "io_test", Config(s), {{"values", std::vector<double>(1000, 1.0)}});
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(-100, std::ios::end);
    file.put('\x5a');
  }
  try {
    read_checkpoint(path);
    FAIL() << "a damaged checkpoint was read";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
  EXPECT_THROW(read_checkpoint((scratch.path / "absent.checkpoint").string()), InputError);
}

}  // namespace
}  // namespace granflow
