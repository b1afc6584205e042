// The shared counting sort against a stable sort by cell: the same order
// with several chunks (dense grid) and with one (sparse grid), and the
// cells' starts and counts.

#include "systems/geometry/counting_sort.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

namespace granflow {
namespace {

void expect_stable_sort(std::size_t n, std::size_t cell_count) {
  std::mt19937 random(11);
  std::vector<std::uint32_t> cell(n);
  for (auto& c : cell) c = static_cast<std::uint32_t>(random() % cell_count);
  std::vector<std::uint32_t> start(cell_count + 1), order(n), count(cell_count), scratch;
  count_scan_fill(cell.data(), n, cell_count, start.data(), order.data(), scratch, count.data());
  std::vector<std::uint32_t> expected(n);
  std::iota(expected.begin(), expected.end(), 0u);
  std::stable_sort(expected.begin(), expected.end(), [&](auto a, auto b) { return cell[a] < cell[b]; });
  EXPECT_EQ(order, expected);
  EXPECT_EQ(start[cell_count], n);
  for (std::size_t c = 0; c < cell_count; ++c) {
    EXPECT_EQ(count[c], start[c + 1] - start[c]);
    for (std::uint32_t k = start[c]; k < start[c + 1]; ++k) ASSERT_EQ(cell[order[k]], c);
  }
  // The scratch stays within twice the items where the grid is sparse.
  EXPECT_LE(scratch.size(), std::max<std::size_t>(2 * n, cell_count));
}

TEST(CountingSort, DenseGridInSeveralChunks) { expect_stable_sort(300000, 1000); }
TEST(CountingSort, SparseGridInOneChunk) { expect_stable_sort(300000, 1000000); }
TEST(CountingSort, NoItems) { expect_stable_sort(0, 5); }

}  // namespace
}  // namespace granflow
