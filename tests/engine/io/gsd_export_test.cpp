// A result's frames as GSD (HOOMD schema): the file starts with GSD's
// header, and read back it holds the same particles, shifted into HOOMD's
// centred box and back. The readers users run (gsd.hoomd, MDAnalysis,
// OVITO) are tried in tests/interop.

#include "engine/io/gsd_export.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "engine/io/gsd_layout.hpp"
#include "engine/io/stored_state.hpp"
#include "small_result.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

TEST(GsdLayout, TypeSizesAndVersionsAreGsds) {
  EXPECT_EQ(gsd_type_size(static_cast<std::uint8_t>(GsdType::uint8)), 1u);
  EXPECT_EQ(gsd_type_size(static_cast<std::uint8_t>(GsdType::int32)), 4u);
  EXPECT_EQ(gsd_type_size(static_cast<std::uint8_t>(GsdType::float32)), 4u);
  EXPECT_EQ(gsd_type_size(static_cast<std::uint8_t>(GsdType::float64)), 8u);
  EXPECT_EQ(gsd_type_size(0), 0u);
  EXPECT_EQ(gsd_type_size(200), 0u);
  EXPECT_EQ(gsd_version(2, 1), 0x20001u);
}

TEST(GsdExport, HeaderAndFramesReadBack) {
  ScratchDirectory scratch("granflow_gsd_export_test_");
  const std::string result = (scratch.path / "result.h5md").string(), gsd = (scratch.path / "result.gsd").string();
  test::write_small_result(result);
  EXPECT_EQ(export_gsd(result, gsd), 2u);
  GsdHeader header;
  std::ifstream(gsd, std::ios::binary).read(reinterpret_cast<char*>(&header), sizeof header);
  EXPECT_EQ(header.magic, gsd_magic);
  EXPECT_STREQ(header.schema, "hoomd");
  const StoredState back = read_stored_state(gsd, -1);
  EXPECT_EQ(back.count, 3u);
  EXPECT_EQ(back.edges, (std::vector<double>{2.0, 3.0, 4.0}));
  for (std::uint32_t k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a)  // single precision, as HOOMD stores positions
      EXPECT_NEAR(back.position[3 * k + a], test::position_of(k, 1)[a], 1e-6);
  EXPECT_EQ(back.mass, (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(back.species, (std::vector<std::int64_t>{0, 0, 1}));
}

}  // namespace
}  // namespace granflow
