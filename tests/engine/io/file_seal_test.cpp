// The seal tells a file as written from one changed afterwards, with plain
// reads, before HDF5 opens it.

#include "engine/io/file_seal.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

void write_bytes(const std::string& path, std::size_t size) {
  std::ofstream out(path, std::ios::binary);
  for (std::size_t k = 0; k < size; ++k) out.put(static_cast<char>(k % 251));
}

TEST(FileSeal, MatchesAsWrittenAndBreaksOnAnyChangedByte) {
  ScratchDirectory scratch("granflow_file_seal_test_");
  const std::string path = (scratch.path / "data.h5").string();
  write_bytes(path, seal_block_bytes + 4096);
  EXPECT_EQ(check_seal(path), SealState::absent);
  seal_file(path);
  EXPECT_EQ(check_seal(path), SealState::matches);
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(seal_block_bytes + 2000));
    file.put('\x01');
  }
  EXPECT_EQ(check_seal(path), SealState::broken);
  seal_file(path);  // sealed again, as an edit on purpose would be
  EXPECT_EQ(check_seal(path), SealState::matches);
}

TEST(FileSeal, DescribesEachState) {
  EXPECT_EQ(describe(SealState::matches), "intact");
  EXPECT_EQ(describe(SealState::absent), "has no granflow seal");
  EXPECT_EQ(describe(SealState::broken), "was changed or damaged after it was written");
}

}  // namespace
}  // namespace granflow
