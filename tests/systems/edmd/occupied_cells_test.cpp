// The occupancy of a neighbourhood, read eight cells at a time, against
// reading each cell's head in turn: every count of cells a prediction asks
// for (up to 64, padded to whole groups), empty and occupied cells mixed,
// offsets on both sides of the origin.

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "systems/edmd/occupied_cells.hpp"

namespace granflow::edmd {
namespace {

TEST(OccupiedCells, MatchesReadingEachHead) {
  std::mt19937_64 rng(11);
  std::vector<std::int32_t> head(4096);
  for (auto& h : head) h = rng() % 2 ? -1 : static_cast<std::int32_t>(rng() % 100000);
  const std::uint32_t origin = 2048;
  for (int count = 1; count <= 64; ++count) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<std::int32_t> offsets((count + occupancy_group - 1) / occupancy_group * occupancy_group, 0);
      for (int k = 0; k < count; ++k) offsets[static_cast<std::size_t>(k)] = static_cast<std::int32_t>(rng() % 4000) - 2000;
      std::int32_t heads[64];
      const std::uint64_t occupied = occupied_cells(head.data(), origin, offsets.data(), count, heads);
      for (int k = 0; k < 64; ++k) {
        const bool listed = k < count;
        const std::int32_t expected = listed ? head[origin + static_cast<std::uint32_t>(offsets[static_cast<std::size_t>(k)])] : -1;
        ASSERT_EQ((occupied >> k) & 1, listed && expected >= 0 ? 1u : 0u) << "count " << count << " cell " << k;
        if (listed && expected >= 0) {
          ASSERT_EQ(heads[k], expected) << "count " << count << " cell " << k;
        }
      }
    }
  }
}

}  // namespace
}  // namespace granflow::edmd
