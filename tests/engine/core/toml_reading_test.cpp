// Configuration text: non-ASCII bytes outside strings and comments are
// refused with their line before toml++ sees them, parse errors name the
// place, and tables flatten to dotted keys.

#include "engine/core/toml_reading.hpp"

#include <gtest/gtest.h>

namespace granflow {
namespace {

std::string message_of(const std::string& text) {
  try {
    parse_toml_text(text, "x.toml", "configuration x.toml");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return {};
}

TEST(TomlReading, NonAsciiIsAllowedInStringsAndCommentsOnly) {
  EXPECT_NO_THROW(require_ascii_outside_strings("a = \"größe\" # Größe\nb = 'µ'\nc = \"\"\"\nä\n\"\"\"\n", "t"));
  EXPECT_NO_THROW(require_ascii_outside_strings("a = \"escaped \\\" quote ä\"\n", "t"));
  const std::string message = message_of("a = 1\nb = 2\nlänge = 3\n");
  EXPECT_NE(message.find("line 3 has a non-ASCII character"), std::string::npos) << message;
  EXPECT_NE(message.find("configuration x.toml"), std::string::npos) << message;
}

TEST(TomlReading, ASyntaxErrorNamesTheFileAndLine) {
  const std::string message = message_of("a = 1\nb = = 2\n");
  EXPECT_NE(message.find("cannot parse configuration x.toml"), std::string::npos) << message;
  EXPECT_NE(message.find("line 2"), std::string::npos) << message;
}

TEST(TomlReading, TablesFlattenIntoDottedKeysInOrder) {
  const toml::table table = parse_toml_text("top = 1\n[collision]\nrestitution = 0.9\n[a.b]\nc = [1, 2]\n", "x.toml", "x");
  std::vector<std::pair<std::string, const toml::node*>> leaves;
  collect_toml_leaves(table, "", leaves);
  std::vector<std::string> keys;
  for (const auto& [key, node] : leaves) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"a.b.c", "collision.restitution", "top"}));
  EXPECT_EQ(leaves[1].second->value<double>(), 0.9);
  EXPECT_TRUE(leaves[0].second->is_array());
}

TEST(TomlReading, AMissingFileIsNamed) {
  try {
    parse_toml_file("/nonexistent/granflow.toml", "configuration /nonexistent/granflow.toml");
    FAIL();
  } catch (const ConfigError& error) {
    EXPECT_STREQ(error.what(), "cannot read configuration /nonexistent/granflow.toml");
  }
}

}  // namespace
}  // namespace granflow
