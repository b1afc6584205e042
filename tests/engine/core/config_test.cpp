// Configuration: every bad key, type or value is an error that names the key
// and says what is allowed.

#include <gtest/gtest.h>

#include "engine/core/config.hpp"

namespace granflow {
namespace {

ConfigSchema schema() {
  ConfigSchema s;
  s.integer("system.count", 10, 1, 1000, "N")
      .real("system.radius", 0.1, 0.0, 1.0, "r", true)
      .choice("system.boundary", "periodic", {"periodic", "reflecting"}, "boundary")
      .boolean("initial.remove_mean_velocity", true, "flag");
  return s;
}

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, DefaultsAndFileValues) {
  const auto s = schema();
  const Config c = Config::from_toml_text(s, "[system]\ncount = 20\nradius = 0.5\n", "test");
  EXPECT_EQ(c.integer("system.count"), 20);
  EXPECT_EQ(c.real("system.radius"), 0.5);
  EXPECT_EQ(c.text("system.boundary"), "periodic");
  EXPECT_TRUE(c.boolean("initial.remove_mean_velocity"));
}

TEST(Config, IntegerIsAcceptedForReal) {
  const auto s = schema();
  EXPECT_EQ(Config::from_toml_text(s, "[system]\nradius = 1\n", "test").real("system.radius"), 1.0);
}

TEST(Config, UnknownKeyIsNamed) {
  const auto s = schema();
  const auto message = error_of([&] { Config::from_toml_text(s, "[system]\ncuont = 20\n", "test"); });
  EXPECT_NE(message.find("unknown configuration key 'system.cuont'"), std::string::npos) << message;
  EXPECT_NE(message.find("system.count"), std::string::npos) << message;
}

TEST(Config, WrongTypeIsNamed) {
  const auto s = schema();
  const auto message = error_of([&] { Config::from_toml_text(s, "[system]\ncount = \"many\"\n", "test"); });
  EXPECT_NE(message.find("'system.count' must be an integer"), std::string::npos) << message;
}

TEST(Config, OutOfRangeShowsAllowedRange) {
  const auto s = schema();
  auto message = error_of([&] { Config::from_toml_text(s, "[system]\nradius = 0.0\n", "test"); });
  EXPECT_NE(message.find("'system.radius' = 0 is out of range: allowed is a number in (0, 1]"), std::string::npos)
      << message;
  message = error_of([&] { Config::from_toml_text(s, "[system]\ncount = 0\n", "test"); });
  EXPECT_NE(message.find("an integer in [1, 1000]"), std::string::npos) << message;
}

TEST(Config, BadChoiceListsChoices) {
  const auto s = schema();
  const auto message = error_of([&] { Config::from_toml_text(s, "[system]\nboundary = \"open\"\n", "test"); });
  EXPECT_NE(message.find("one of: periodic, reflecting"), std::string::npos) << message;
}

TEST(Config, SyntaxErrorIsReported) {
  const auto s = schema();
  EXPECT_NE(error_of([&] { Config::from_toml_text(s, "[system\ncount = 1\n", "test"); }).find("cannot parse test"),
            std::string::npos);
}

TEST(Config, OverridesAreTypedAndChecked) {
  const auto s = schema();
  Config c(s);
  c.apply_override("system.count=42");
  c.apply_override("system.boundary=reflecting");
  c.apply_override("initial.remove_mean_velocity=false");
  EXPECT_EQ(c.integer("system.count"), 42);
  EXPECT_EQ(c.text("system.boundary"), "reflecting");
  EXPECT_FALSE(c.boolean("initial.remove_mean_velocity"));
  EXPECT_NE(error_of([&] { c.apply_override("system.count=4.5"); }).find("'system.count' must be an integer"),
            std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("system.radius=abc"); }).find("'system.radius' must be a number"),
            std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("nonsense"); }).find("section.key=value"), std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("system.size=3"); }).find("unknown configuration key 'system.size'"),
            std::string::npos);
}

TEST(Config, ResolvedTomlRoundTrips) {
  const auto s = schema();
  Config c(s);
  c.apply_override("system.radius=0.25");
  const Config again = Config::from_toml_text(s, c.to_toml(), "resolved");
  EXPECT_EQ(again.values(), c.values());
}

ConfigSchema list_schema() {
  ConfigSchema wall;
  wall.choice("axis", "y", {"x", "y", "z"}, "normal axis")
      .real("position", 0.0, 0.0, 1.0, "where")
      .real("restitution", 1.0, 0.0, 1.0, "e");
  ConfigSchema s;
  s.real_array("system.cells", {10, 10, 10}, 1, 1e6, 3, 3, "cells per axis")
      .table_array("walls", std::move(wall), 0, 6, "walls of the box");
  return s;
}

TEST(Config, ListsOfNumbersAndOfTablesFromFilesAndSet) {
  const auto s = list_schema();
  Config c = Config::from_toml_text(
      s, "walls = [{axis = 'x', position = 0.5}]\n[system]\ncells = [46, 46, 46]\n", "test");
  EXPECT_EQ(c.reals("system.cells"), (std::vector<double>{46, 46, 46}));
  ASSERT_EQ(c.tables("walls").size(), 1u);
  EXPECT_EQ(c.tables("walls")[0].text("axis"), "x");
  EXPECT_EQ(c.tables("walls")[0].real("restitution"), 1.0);  // the element's default
  c.apply_override("system.cells = [8, 16, 32]");
  EXPECT_EQ(c.reals("system.cells"), (std::vector<double>{8, 16, 32}));
  c.apply_override("walls=[{axis = 'y', restitution = 0.9}, {axis = 'z'}]");
  EXPECT_EQ(c.tables("walls").size(), 2u);
  EXPECT_EQ(c.tables("walls")[0].real("restitution"), 0.9);
  // The resolved configuration is TOML that reads back to the same values.
  const Config again = Config::from_toml_text(s, c.to_toml(), "round trip");
  EXPECT_EQ(again.values(), c.values());
  // [[walls]] tables in the file form.
  EXPECT_EQ(Config::from_toml_text(s, "[[walls]]\naxis = 'z'\n[[walls]]\nposition = 1.0\n", "test")
                .tables("walls")[1].real("position"),
            1.0);
}

TEST(Config, ListErrorsNameTheKeyAndTheItem) {
  const auto s = list_schema();
  Config c(s);
  EXPECT_NE(error_of([&] { c.apply_override("system.cells=[46, 46]"); }).find(
                "'system.cells' has 2 items: allowed is a list of 3 numbers in [1, 1000000]"),
            std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("system.cells=[46, 0, 46]"); }).find("holds 0, out of range"),
            std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("walls=[{axis = 'w'}]"); }).find("walls[0]: configuration key 'axis'"),
            std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("walls=[{axes = 'x'}]"); }).find("unknown key 'axes' in walls[0]"),
            std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("system.cells=[1, 2"); }).find("cannot parse --set system.cells"),
            std::string::npos);
}

TEST(Config, NonAsciiOutsideStringsIsRefusedBeforeParsing) {
  const auto s = schema();
  // Allowed inside strings and comments, single- and multi-line.
  EXPECT_EQ(Config::from_toml_text(s, "# caf\u00e9\n[system]\nboundary = 'periodic' # \u00e9\n", "test")
                .text("system.boundary"),
            "periodic");
  EXPECT_NE(error_of([&] { Config::from_toml_text(s, "x = \"\u00e9\"\n[system]\nc\u00a1ount = 3\n", "test"); })
                .find("cannot parse test: line 3 has a non-ASCII character outside a string or comment"),
            std::string::npos);
  EXPECT_NE(error_of([&] { Config::from_toml_text(s, "a = \"\"\"x\n\u00e9\"\"\"\n\u00e9 = 1\n", "test"); })
                .find("line 3 has a non-ASCII"),
            std::string::npos);
}

TEST(Config, SetTrimsSpacesAndReadsIntegersWrittenWithExponents) {
  const auto s = schema();
  Config c(s);
  c.apply_override("  system.count =  2e2 ");
  EXPECT_EQ(c.integer("system.count"), 200);
  EXPECT_NE(error_of([&] { c.apply_override("system.count=2.5e0"); }).find("must be an integer"), std::string::npos);
}

}  // namespace
}  // namespace granflow
