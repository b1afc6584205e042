// `granflow --version` and every file's provenance name this build.

#include "engine/io/version.hpp"

#include <gtest/gtest.h>

#include <regex>

namespace granflow {
namespace {

TEST(Version, NamesTheVersionRevisionAndBuild) {
  const BuildInfo& info = build_info();
  EXPECT_TRUE(std::regex_match(std::string(info.version), std::regex(R"(\d+\.\d+\.\d+)"))) << info.version;
  EXPECT_GT(std::string(info.revision).size(), 0u);
  EXPECT_GT(std::string(info.compiler).size(), 0u);
  const std::string text = version_text();
  EXPECT_EQ(text.rfind(std::string("granflow ") + info.version, 0), 0u) << text;
  EXPECT_NE(text.find(info.build_type), std::string::npos) << text;
}

}  // namespace
}  // namespace granflow
