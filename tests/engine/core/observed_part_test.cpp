// ObservedPart as rank 0 of two sees it: totals add the ranks' values in
// rank order, and whole_field puts each rank's layers of a cell field in
// their place in the whole grid, along any axis.

#include "engine/core/observed_part.hpp"

#include <gtest/gtest.h>

#include "tests/first_of_two.hpp"

namespace granflow {
namespace {

// Value of cell (x, y, z) on a 3 x 2 x 4 grid, x fastest.
double cell_value(int x, int y, int z) { return 100.0 * z + 10.0 * y + x; }

// The cells of layers [low, high) along `axis`, in the whole grid's order.
std::vector<double> layers(int axis, int low, int high) {
  std::vector<double> out;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x) {
        const int along = axis == 0 ? x : axis == 1 ? y : z;
        if (along >= low && along < high) out.push_back(cell_value(x, y, z));
      }
  return out;
}

TEST(ObservedPart, TotalsAreTheRanksValuesAddedInRankOrder) {
  FirstOfTwo ranks;
  ranks.from_second = {{2.5, -1.0}, {7.0}};
  const ObservedPart part(ranks, 2, 0, 1);
  EXPECT_EQ(part.total(std::vector<double>{1.0, 4.0}), (std::vector<double>{3.5, 3.0}));
  EXPECT_EQ(part.total(1.0), 8.0);
  EXPECT_TRUE(part.writes());
  EXPECT_FALSE(part.whole());
}

TEST(ObservedPart, WholeFieldPlacesEachRanksLayersAlongAnyAxis) {
  const std::vector<double> whole = layers(0, 0, 3);
  for (const auto& [axis, split, length] : {std::tuple{2, 1, 4}, std::tuple{0, 2, 3}, std::tuple{1, 1, 2}}) {
    FirstOfTwo ranks;
    ranks.from_second = {{static_cast<double>(split), static_cast<double>(length)}, layers(axis, split, length)};
    const ObservedPart part(ranks, axis, 0, split);
    EXPECT_EQ(part.whole_field(layers(axis, 0, split), {3, 2, 4}, 1), whole) << "slabs along axis " << axis;
    EXPECT_EQ(part.layer_low(), 0);
    EXPECT_EQ(part.layer_high(99), split);
  }
}

TEST(ObservedPart, TheWholeIsItsOwnField) {
  const ObservedPart whole;
  EXPECT_TRUE(whole.whole());
  EXPECT_EQ(whole.total(2.0), 2.0);
  EXPECT_EQ(whole.layer_high(7), 7);
  EXPECT_EQ(whole.whole_field({1.0, 2.0}, {2}, 1), (std::vector<double>{1.0, 2.0}));
}

}  // namespace
}  // namespace granflow
