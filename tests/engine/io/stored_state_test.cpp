// A run may start from a frame of a granflow result, a GSD file (HOOMD
// schema) or an extended XYZ file: each comes back in granflow's box [0, L)
// with its columns, and a frame that is not there is named.

#include "engine/io/stored_state.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "engine/core/input_error.hpp"
#include "small_result.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

TEST(StoredState, AFrameOfAResultFileInIdOrder) {
  ScratchDirectory scratch("granflow_stored_state_test_");
  const std::string path = (scratch.path / "result.h5md").string();
  test::write_small_result(path);
  const StoredState last = read_stored_state(path, -1), first = read_stored_state(path, 0);
  EXPECT_EQ(last.count, 3u);
  EXPECT_EQ(last.dimension, 3u);
  EXPECT_EQ(last.edges, (std::vector<double>{2.0, 3.0, 4.0}));
  EXPECT_EQ(last.periodic, (std::vector<bool>{true, true, true}));
  for (std::uint32_t k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(last.position[3 * k + a], test::position_of(k, 1)[a]);
      EXPECT_EQ(first.position[3 * k + a], test::position_of(k, 0)[a]);
      EXPECT_EQ(last.velocity[3 * k + a], test::velocity_of(k, 1)[a]);
    }
  EXPECT_EQ(last.mass, (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(last.species, (std::vector<std::int64_t>{0, 0, 1}));
  try {
    read_stored_state(path, 2);
    FAIL() << "frame 2 of 2 was read";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("holds 2 frames"), std::string::npos) << error.what();
  }
}

TEST(StoredState, AnExtendedXyzFrameAsAseWritesIt) {
  ScratchDirectory scratch("granflow_stored_state_test_");
  const std::string path = (scratch.path / "frame.xyz").string();
  {
    std::ofstream out(path);
    out << "2\n"
        << "Lattice=\"2.0 0.0 0.0 0.0 3.0 0.0 0.0 0.0 4.0\" Properties=species:S:1:pos:R:3:velo:R:3:masses:R:1 "
           "pbc=\"T T F\"\n"
        << "H 0.5 1.0 1.5 1.0 0.0 0.0 2.0\n"
        << "He 1.5 2.0 3.5 0.0 -1.0 0.0 4.0\n";
  }
  const StoredState s = read_stored_state(path, -1);
  EXPECT_EQ(s.count, 2u);
  EXPECT_EQ(s.edges, (std::vector<double>{2.0, 3.0, 4.0}));
  EXPECT_EQ(s.periodic, (std::vector<bool>{true, true, false}));
  EXPECT_EQ(s.position, (std::vector<double>{0.5, 1.0, 1.5, 1.5, 2.0, 3.5}));
  EXPECT_EQ(s.velocity, (std::vector<double>{1.0, 0.0, 0.0, 0.0, -1.0, 0.0}));
  EXPECT_EQ(s.mass, (std::vector<double>{2.0, 4.0}));
}

TEST(StoredState, AFileOfNoKnownFormatIsNamed) {
  ScratchDirectory scratch("granflow_stored_state_test_");
  const std::string path = (scratch.path / "notes.txt").string();
  std::ofstream(path) << "not a particle state\n";
  try {
    read_stored_state(path, 0);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace granflow
