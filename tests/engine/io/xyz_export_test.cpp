// A result's frames as extended XYZ: one block per frame with the count, a
// comment line of key=value pairs (Lattice, pbc, Time, Properties) and one
// line per particle in id order; read back it holds the same particles.
// ASE and OVITO themselves are tried in tests/interop.

#include "engine/io/xyz_export.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "engine/io/stored_state.hpp"
#include "small_result.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

TEST(XyzExport, OneBlockPerFrameThatReadsBack) {
  ScratchDirectory scratch("granflow_xyz_export_test_");
  const std::string result = (scratch.path / "result.h5md").string(), xyz = (scratch.path / "result.xyz").string();
  test::write_small_result(result);
  EXPECT_EQ(export_extended_xyz(result, xyz), 2u);
  std::ifstream in(xyz);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 2u * (2 + 3));
  for (std::size_t frame = 0; frame < 2; ++frame) {
    EXPECT_EQ(lines[frame * 5], "3");
    const std::string& comment = lines[frame * 5 + 1];
    EXPECT_NE(comment.find("Lattice=\"2"), std::string::npos) << comment;
    EXPECT_NE(comment.find("pbc=\"T T T\""), std::string::npos) << comment;
    EXPECT_NE(comment.find("Properties="), std::string::npos) << comment;
    EXPECT_NE(comment.find("Time="), std::string::npos) << comment;
  }
  const StoredState back = read_stored_state(xyz, 0);
  EXPECT_EQ(back.count, 3u);
  for (std::uint32_t k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(back.position[3 * k + a], test::position_of(k, 0)[a], 1e-12);
  EXPECT_EQ(back.mass, (std::vector<double>{1.0, 2.0, 3.0}));
}

}  // namespace
}  // namespace granflow
