// A checkpoint gives back the exact state and configuration it was written
// with, and one that was damaged after writing is refused by name.

#include "engine/io/checkpoint_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "engine/io/file_seal.hpp"
#include "engine/io/h5md_reader.hpp"
#include "tests/first_of_two.hpp"
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

// Over ranks the particle arrays are written block by block as the ranks
// send their rows, and read back by block: the file is the one a single
// writer of the whole state makes, checksum included. Rank 1's 300 000
// rows span two blocks of 2^18, so that a block takes rows of both ranks.
TEST(CheckpointFile, RowsWrittenByRankMakeTheFileOfTheWholeState) {
  ScratchDirectory scratch("granflow_checkpoint_test_");
  const std::string by_rank = (scratch.path / "by_rank.checkpoint").string();
  const std::string whole_path = (scratch.path / "whole.checkpoint").string();
  const ConfigSchema s = schema();
  const Config config(s);
  const std::size_t theirs = 300000;
  // Besides the particles' rows, an array of rows of its own (a kept
  // object's pairs): 3 on this rank, 5 on the other, 2 values each.
  RankRows mine{2,
                {{"world/position", {0.5, 1.5, 2.5, 3.5, 4.5, 5.5}},
                 {"world/id", {7.0, 3.0}},
                 {"kept/lists/pairs", {1.0, 2.0, 3.0, 4.0, 5.0, 6.0}}},
                {{"kept/lists/pairs", 3}}};
  const std::vector<double> their_pairs{10.0, 11.0, 12.0, 13.0, 14.0, 15.0, 16.0, 17.0, 18.0, 19.0};
  std::vector<double> their_positions(3 * theirs), their_ids(theirs);
  for (std::size_t i = 0; i < 3 * theirs; ++i) their_positions[i] = 0.25 * static_cast<double>(i) - 1e5;
  for (std::size_t i = 0; i < theirs; ++i) their_ids[i] = static_cast<double>(i + 100);
  const StateMap state{{"clock", {0.5, 12.0}},
                       {"world.size", {static_cast<double>(2 + theirs)}},
                       {"world/id.width", {1.0}},
                       {"world/position.width", {3.0}},
                       {"zeta", {-1.0}}};
  StateMap whole = state;
  for (const auto& [name, values] : mine.arrays) whole[name] = values;
  whole["kept/lists/pairs"].insert(whole["kept/lists/pairs"].end(), their_pairs.begin(), their_pairs.end());
  whole["world/position"].insert(whole["world/position"].end(), their_positions.begin(), their_positions.end());
  whole["world/id"].insert(whole["world/id"].end(), their_ids.begin(), their_ids.end());

  FirstOfTwo ranks;
  const auto rows_from = [](const std::vector<double>& values, std::size_t first, std::size_t last) {
    return std::vector<double>(values.begin() + static_cast<std::ptrdiff_t>(first),
                               values.begin() + static_cast<std::ptrdiff_t>(last));
  };
  const std::size_t block = std::size_t{1} << 18;  // rows; rank 0 holds rows 0 and 1
  // Their rows of each array in name order, then each array's values and blocks.
  ranks.from_second = {{5.0, static_cast<double>(theirs), static_cast<double>(theirs)},
                       {10.0},
                       their_pairs,
                       {static_cast<double>(theirs)},  // world/id
                       rows_from(their_ids, 0, block - 2),
                       rows_from(their_ids, block - 2, theirs),
                       {static_cast<double>(3 * theirs)},
                       rows_from(their_positions, 0, 3 * (block - 2)),
                       rows_from(their_positions, 3 * (block - 2), 3 * theirs)};
  write_checkpoint_by_rank(by_rank, "io_test", config, state, mine, ranks);
  EXPECT_TRUE(ranks.from_second.empty());
  write_checkpoint(whole_path, "io_test", config, whole);

  EXPECT_EQ(H5mdReader(by_rank).string_attribute("/checkpoint", "checksum"),
            H5mdReader(whole_path).string_attribute("/checkpoint", "checksum"));
  EXPECT_EQ(read_checkpoint(by_rank).state, whole);

  const CheckpointContents in_file = read_checkpoint(by_rank, {true, true});
  StateMap whole_arrays = state;
  whole_arrays["kept/lists/pairs"] = whole.at("kept/lists/pairs");
  EXPECT_EQ(in_file.state, whole_arrays);
  ASSERT_EQ(in_file.rows.sizes(), (std::map<std::string, std::size_t>{{"world/id", 2 + theirs},
                                                                       {"world/position", 3 * (2 + theirs)}}));
  EXPECT_EQ(in_file.rows.read("world/position", 3, 6), rows_from(whole.at("world/position"), 3, 9));
  EXPECT_EQ(in_file.rows.read("world/id", block, 5), rows_from(whole.at("world/id"), block, block + 5));
}

// A value changed in an array left in the file is caught by the checksum,
// which reads it through in blocks.
TEST(CheckpointFile, ADamagedRowArrayIsRefusedWhenReadByBlock) {
  ScratchDirectory scratch("granflow_checkpoint_test_");
  const std::string path = (scratch.path / "rows.checkpoint").string();
  const ConfigSchema s = schema();
  write_checkpoint(path, "io_test", Config(s),
                   {{"world.size", {4.0}}, {"world/position", {1.0, 2.0, 3.0, 4.0}}, {"world/position.width", {1.0}}});
  EXPECT_NO_THROW(read_checkpoint(path, {true, true}));
  {
    const H5mdReader reader(path);
    ASSERT_EQ(reader.string_array("/checkpoint/names")[1], "world/position");
  }
  // Rewritten in place through HDF5, then resealed, as a tool editing the
  // file on purpose would: only the checksum tells the change.
  std::vector<double> changed{1.0, 2.0, 3.0, 4.5};
  {
    H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose, "open");
    H5Handle dataset(H5Dopen2(file, "/checkpoint/values/1", H5P_DEFAULT), H5Dclose, "open values");
    ASSERT_GE(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, changed.data()), 0);
  }
  seal_file(path);
  EXPECT_THROW(read_checkpoint(path, {true, true}), InputError);
  EXPECT_THROW(read_checkpoint(path), InputError);
  // A rank that leaves the checking to rank 0 reads it as it stands.
  EXPECT_EQ(read_checkpoint(path, {true, false}).rows.read("world/position", 0, 4), changed);
}

}  // namespace
}  // namespace granflow
