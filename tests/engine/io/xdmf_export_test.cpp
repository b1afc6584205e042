// XDMF over a result: one grid per frame in a temporal collection with the
// frames' times, its arrays in a companion file beside it; a field grid
// names each field with its shape. ParaView itself reads them in
// tests/interop.

#include "engine/io/xdmf_export.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "small_result.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto k = text.find(what); k != std::string::npos; k = text.find(what, k + 1)) ++n;
  return n;
}

TEST(XdmfExport, OneGridPerFrameWithItsTime) {
  ScratchDirectory scratch("granflow_xdmf_export_test_");
  const std::string result = (scratch.path / "result.h5md").string(), xdmf = (scratch.path / "result.xdmf").string();
  test::write_small_result(result);
  EXPECT_EQ(export_xdmf(result, xdmf), 2u);
  const std::string text = read_text(xdmf);
  EXPECT_NE(text.find("CollectionType=\"Temporal\""), std::string::npos);
  EXPECT_EQ(occurrences(text, "<Time "), 2u);
  EXPECT_NE(text.find("Value=\"0.5\""), std::string::npos) << text;
  EXPECT_TRUE(std::filesystem::exists(scratch.path / "result.xdmf.h5"));  // the companion
}

TEST(XdmfExport, AFieldGridNamesEachFieldAndItsShape) {
  ScratchDirectory scratch("granflow_xdmf_export_test_");
  const std::string result = (scratch.path / "fields.h5md").string(), xdmf = (scratch.path / "fields.xdmf").string();
  write_field_xdmf(result, xdmf, {4, 3, 2}, {0.0, 1.0, 2.0}, {{"density", 1}, {"velocity", 3}});
  const std::string text = read_text(xdmf);
  EXPECT_EQ(occurrences(text, "<Time "), 3u);
  EXPECT_EQ(occurrences(text, "Name=\"density\""), 3u);
  EXPECT_EQ(occurrences(text, "Name=\"velocity\""), 3u);
  EXPECT_NE(text.find("Dimensions=\"2 3 4 3\""), std::string::npos) << text;  // cells z y x, components
}

}  // namespace
}  // namespace granflow
