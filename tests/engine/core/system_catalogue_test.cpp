// `granflow list` shows every system whose header describes it: a
// description registers itself when its header is part of the program.

#include "engine/core/system_catalogue.hpp"

#include <gtest/gtest.h>

namespace granflow {
namespace {

const SystemDescription described{"test_described_system", "a system only this test knows"};

TEST(SystemCatalogue, ADescriptionRegistersItsSystem) {
  const auto& catalogue = system_catalogue();
  ASSERT_TRUE(catalogue.count("test_described_system"));
  EXPECT_EQ(catalogue.at("test_described_system"), "a system only this test knows");
  // Described again (a header included twice over), the last text holds, once.
  const SystemDescription again{"test_described_system", "described again"};
  EXPECT_EQ(system_catalogue().at("test_described_system"), "described again");
}

}  // namespace
}  // namespace granflow
