// A run that cannot fit is refused before it allocates, naming its setting.

#include "engine/core/memory_check.hpp"

#include <gtest/gtest.h>

namespace granflow {
namespace {

TEST(MemoryCheck, ReadsTheAvailableMemoryOfThisMachine) {
  const double available = available_memory_bytes();
  EXPECT_GT(available, 1e6);   // /proc/meminfo on Linux: some megabytes at least
  EXPECT_LT(available, 1e15);  // and not a misread unit
}

TEST(MemoryCheck, RefusesWhatExceedsItNamingTheSetting) {
  EXPECT_NO_THROW(require_memory("system.count = 10", 1e3));
  try {
    require_memory("system.count = 2000000000000", 1e18);
    FAIL() << "1e18 bytes were accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("system.count = 2000000000000"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("1e+09 GB"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace granflow
