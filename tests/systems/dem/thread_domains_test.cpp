// The split of the spheres and slabs over threads: every piece of work is
// done exactly once whoever does it, and the domains are contiguous,
// cover everything and balance the cost to within a slab.

#include "systems/dem/thread_domains.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <numeric>
#include <vector>

namespace granflow::dem {
namespace {

TEST(ThreadDomains, EvenDomainsCoverTheSpheresInOrder) {
  const ThreadDomains d = even_domains(10, 3);
  ASSERT_EQ(d.count(), 3u);
  EXPECT_EQ(d.sphere, (std::vector<std::uint32_t>{0, 3, 6, 10}));
  EXPECT_TRUE(d.covers(10));
  EXPECT_FALSE(d.covers(11));
}

TEST(ThreadDomains, BalancedDomainsSplitTheCostWithinOneSlab) {
  // 12 slabs, dense at the bottom like a bed under gravity, empty above.
  const std::vector<std::uint32_t> per_slab = {90, 80, 80, 70, 60, 50, 30, 10, 0, 0, 0, 0};
  std::vector<std::uint32_t> slabs(per_slab.size() + 1, 0);
  std::partial_sum(per_slab.begin(), per_slab.end(), slabs.begin() + 1);
  const std::uint32_t n = slabs.back();
  // Six pairs per sphere.
  std::vector<std::uint32_t> offsets(n + 1);
  for (std::uint32_t m = 0; m <= n; ++m) offsets[m] = 6 * m;
  for (std::size_t threads : {1, 2, 3, 5}) {
    const ThreadDomains d = balanced_domains(slabs, offsets, threads);
    ASSERT_EQ(d.count(), threads);
    EXPECT_EQ(d.slab.front(), 0u);
    EXPECT_EQ(d.slab.back(), per_slab.size());
    EXPECT_TRUE(d.covers(n));
    const double share = 8.0 * n / static_cast<double>(threads);  // cost 6 + 2 per sphere
    for (std::size_t k = 0; k < threads; ++k) {
      EXPECT_LE(d.slab[k], d.slab[k + 1]);
      EXPECT_EQ(d.sphere[k], slabs[d.slab[k]]);
      // Each boundary is the slab edge nearest its target: off by at most half the largest slab.
      const double cost = 8.0 * (d.sphere[k + 1] - d.sphere[k]);
      EXPECT_NEAR(cost, share, 8.0 * 90.0) << threads << " threads, domain " << k;
    }
  }
}

TEST(ThreadDomains, EveryPieceIsDoneOnceOnAnyThreadCount) {
  const std::vector<std::size_t> pieces = {7, 0, 13, 1};
  for (int threads : {1, 2, 4}) {
    tbb::task_arena arena(threads);
    std::vector<std::vector<std::atomic<int>>> done(pieces.size());
    for (std::size_t d = 0; d < pieces.size(); ++d) done[d] = std::vector<std::atomic<int>>(pieces[d]);
    for (int repeat = 0; repeat < 50; ++repeat) {
      arena.execute([&] {
        for_each_piece(pieces, [&](std::size_t d, std::size_t k) {
          ASSERT_LT(d, pieces.size());
          ASSERT_LT(k, pieces[d]);
          ++done[d][k];
        });
      });
    }
    for (std::size_t d = 0; d < pieces.size(); ++d)
      for (std::size_t k = 0; k < pieces[d]; ++k) EXPECT_EQ(done[d][k], 50) << threads << " threads, piece " << d << "/" << k;
  }
}

TEST(ThreadDomains, SphereRunsCoverEachSphereOnce) {
  const ThreadDomains d = even_domains(2000, 2);
  std::vector<std::atomic<int>> seen(2000);
  tbb::task_arena arena(2);
  arena.execute([&] {
    for_each_sphere_run(
        d, [&](std::size_t, std::size_t from, std::size_t to) {
          for (std::size_t i = from; i < to; ++i) ++seen[i];
        },
        300);
  });
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << i;
}

}  // namespace
}  // namespace granflow::dem
