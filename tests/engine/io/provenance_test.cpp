// What /provenance records: the command line as given, the host and user,
// a UTC timestamp in ISO 8601 and the thread limit.

#include "engine/io/provenance.hpp"

#include <gtest/gtest.h>

#include <regex>

namespace granflow {
namespace {

TEST(Provenance, RecordsTheCommandLineWordForWord) {
  const char* argv[] = {"granflow", "run", "a file.toml", "--set", "run.t_stop=2"};
  record_command_line(5, argv);
  const std::string& line = recorded_command_line();
  EXPECT_NE(line.find("granflow run"), std::string::npos) << line;
  EXPECT_NE(line.find("run.t_stop=2"), std::string::npos) << line;
  // A word with a space stays one word when the line is pasted back into a shell.
  EXPECT_NE(line.find("'a file.toml'"), std::string::npos) << line;
}

TEST(Provenance, TimestampHostUserAndThreads) {
  EXPECT_TRUE(std::regex_match(utc_timestamp(), std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)"))) << utc_timestamp();
  EXPECT_FALSE(host_name().empty());
  EXPECT_FALSE(user_name().empty());
  EXPECT_GE(thread_limit(), 1);
}

}  // namespace
}  // namespace granflow
