// ordered_sums: the sums of a whole system split into contiguous ranges,
// one message per range put together in range order, have the bits of the
// whole system's own sums, however the ranges fall on the chunks (shorter
// than a chunk, empty, on a chunk boundary or not), with terms that skip
// every bin. Grouping the same terms by range instead does not.

#include "engine/core/ordered_sums.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "engine/core/deterministic_sum.hpp"

namespace granflow {
namespace {

constexpr std::size_t width = 2;

// Terms of widely different sizes, so that their grouping shows in the last bits.
struct Terms {
  std::vector<std::size_t> bin;
  std::vector<double> value;
  Terms(std::size_t n, std::size_t bins, std::uint64_t seed) {
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
      // Runs of neighbours share a bin, as spheres in cell order share a height.
      const double u = unit(random);
      bin.push_back(u < 0.05 ? no_bin : std::min(bins - 1, i * bins / n + (u < 0.3 ? 1 : 0)));
      value.push_back(std::pow(10.0, 8.0 * unit(random) - 4.0) * (unit(random) < 0.5 ? -1.0 : 1.0));
    }
  }
  // The term of the whole's index `from + i`.
  auto from(std::size_t from) const {
    return [this, from](std::size_t i, double* values) {
      values[0] = value[from + i];
      values[1] = value[from + i] * value[from + i];
      return bin[from + i];
    };
  }
};

std::vector<double> split_sums(const Terms& terms, const std::vector<std::size_t>& bounds, std::size_t bins) {
  std::vector<double> all;
  for (std::size_t r = 0; r + 1 < bounds.size(); ++r) {
    const std::vector<double> message = part_message(bounds[r], bounds[r + 1] - bounds[r], width, terms.from(bounds[r]));
    all.insert(all.end(), message.begin(), message.end());
  }
  return sums_from_messages(all, bins, width);
}

TEST(OrderedSums, AnySplitIntoRangesGivesTheWholesBits) {
  const std::size_t n = 5 * ordered_chunk + 123, bins = 7;
  const Terms terms(n, bins, 11);
  const std::vector<double> whole = ordered_sums(n, bins, width, terms.from(0));
  const std::size_t c = ordered_chunk;
  for (const std::vector<std::size_t>& bounds : std::vector<std::vector<std::size_t>>{
           {0, n},
           {0, c, n},
           {0, c / 2, n},
           {0, 2 * c + 17, 2 * c + 17, 2 * c + 40, 3 * c - 1, n},  // an empty range; two inside one chunk
           {0, 100, 200, 300, 4 * c, n},
           {0, n - 1, n}}) {
    EXPECT_EQ(split_sums(terms, bounds, bins), whole) << "ranges starting at " << bounds[1];
  }
  std::mt19937_64 random(5);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<std::size_t> bounds{0, n};
    for (int k = 0; k < 1 + trial % 6; ++k) bounds.push_back(std::uniform_int_distribution<std::size_t>(0, n)(random));
    std::sort(bounds.begin(), bounds.end());
    EXPECT_EQ(split_sums(terms, bounds, bins), whole) << "trial " << trial;
  }
}

TEST(OrderedSums, GroupingByRangeInsteadDiffersInTheLastBits) {
  const std::size_t n = 3 * ordered_chunk, bins = 1;
  const Terms terms(n, bins, 3);
  const double whole = ordered_sums(n, bins, width, terms.from(0))[0];
  int differing = 0;
  for (std::size_t split = 1000; split < n; split += 1500) {
    const double by_range = ordered_sums(split, bins, width, terms.from(0))[0] +
                            ordered_sums(n - split, bins, width, terms.from(split))[0];
    EXPECT_NEAR(by_range, whole, 1e-9 * std::abs(whole) + 1e-3);
    differing += by_range != whole;
    EXPECT_EQ(split_sums(terms, {0, split, n}, bins)[0], whole);
  }
  EXPECT_GT(differing, 0) << "these terms are too tame to show a grouping";
}

TEST(OrderedSums, OneBinOfTermsThatAllCountIsDeterministicSum) {
  const std::size_t n = 4 * ordered_chunk + 7;
  const Terms terms(n, 1, 9);
  const double expected = deterministic_sum(n, [&](std::size_t i) { return terms.value[i]; });
  const auto every = [&](std::size_t i, double* values) {
    values[0] = terms.value[i];
    return std::size_t{0};
  };
  EXPECT_EQ(ordered_sums(n, 1, 1, every)[0], expected);
}

TEST(OrderedSums, MessagesThatDoNotFollowEachOtherAreRefused) {
  const Terms terms(100, 2, 1);
  std::vector<double> all = part_message(0, 50, width, terms.from(0));
  const std::vector<double> gap = part_message(60, 40, width, terms.from(60));
  all.insert(all.end(), gap.begin(), gap.end());
  EXPECT_THROW(sums_from_messages(all, 2, width), std::runtime_error);
  const std::vector<double> early(all.begin(), all.begin() + 5);
  EXPECT_THROW(sums_from_messages(early, 2, width), std::runtime_error);
}

}  // namespace
}  // namespace granflow
