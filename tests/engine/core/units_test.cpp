// Every unit granflow writes is a valid H5MD unit string: symbols separated
// by single spaces, each with an optional signed integer power, and the
// derived units are the products of the base ones they stand for.

#include "engine/core/units.hpp"

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <sstream>

namespace granflow {
namespace {

// Unit string -> power of each symbol.
std::map<std::string, int> powers(const std::string& text) {
  std::map<std::string, int> out;
  std::istringstream in(text);
  std::string token;
  static const std::regex symbol_power("([A-Za-z]+)(-?[0-9]+)?");
  while (in >> token) {
    std::smatch m;
    if (!std::regex_match(token, m, symbol_power)) throw std::invalid_argument("not a unit token: " + token);
    out[m[1]] += m[2].matched ? std::stoi(m[2]) : 1;
  }
  return out;
}

TEST(Units, EveryUnitIsAValidH5mdString) {
  for (const char* u : {unit::length, unit::area, unit::mass, unit::time, unit::velocity, unit::acceleration,
                        unit::energy, unit::force, unit::diffusivity, unit::rate, unit::per_velocity, unit::angle}) {
    EXPECT_TRUE(std::regex_match(std::string(u), std::regex("[A-Za-z]+(-?[0-9]+)?( [A-Za-z]+(-?[0-9]+)?)*"))) << u;
  }
  EXPECT_STREQ(unit::none, "1");  // H5MD's dimensionless unit
}

TEST(Units, DerivedUnitsAreProductsOfLengthMassAndTime) {
  using P = std::map<std::string, int>;
  EXPECT_EQ(powers(unit::area), (P{{"L", 2}}));
  EXPECT_EQ(powers(unit::velocity), (P{{"L", 1}, {"T", -1}}));
  EXPECT_EQ(powers(unit::acceleration), (P{{"L", 1}, {"T", -2}}));
  EXPECT_EQ(powers(unit::energy), (P{{"M", 1}, {"L", 2}, {"T", -2}}));
  EXPECT_EQ(powers(unit::force), (P{{"M", 1}, {"L", 1}, {"T", -2}}));
  EXPECT_EQ(powers(unit::diffusivity), (P{{"L", 2}, {"T", -1}}));
  EXPECT_EQ(powers(unit::rate), (P{{"T", -1}}));
  EXPECT_EQ(powers(unit::per_velocity), (P{{"T", 1}, {"L", -1}}));
}

}  // namespace
}  // namespace granflow
