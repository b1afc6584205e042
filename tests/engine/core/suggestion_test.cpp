// "Did you mean": edit distance with swaps, the closest key, the last part
// of a dotted key, and nothing where nothing is close.

#include "engine/core/suggestion.hpp"

#include <gtest/gtest.h>

namespace granflow {
namespace {

TEST(Suggestion, EditDistanceCountsASwapOnce) {
  EXPECT_EQ(edit_distance("count", "count"), 0u);
  EXPECT_EQ(edit_distance("cuont", "count"), 1u);  // neighbours swapped
  EXPECT_EQ(edit_distance("cont", "count"), 1u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
}

TEST(Suggestion, ClosestNameOrNone) {
  const std::vector<std::string> keys{"system.count", "system.radius", "collision.restitution"};
  EXPECT_EQ(closest_name("system.cuont", keys), "system.count");
  EXPECT_EQ(closest_name("restitution", keys), "collision.restitution");
  EXPECT_FALSE(closest_name("output.interval", keys).has_value());
}

}  // namespace
}  // namespace granflow
