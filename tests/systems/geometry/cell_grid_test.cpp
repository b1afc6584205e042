// The shared cell geometry against brute force: the cell of a point, and
// the block of cells around a cell (each once, wrapped or cut at the edges).

#include "systems/geometry/cell_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

namespace granflow {
namespace {

TEST(CellGrid, ThePointsCellAndTheEdgeCellsOfPointsOutside) {
  const CellGrid<2> grid({-1.0, 0.0}, {4.0, 3.0}, {4, 3}, {false, true});
  EXPECT_EQ(grid.cell_count(), 12u);
  EXPECT_EQ(grid.cell_of(std::array<double, 2>{-0.5, 0.5}), 0u);
  EXPECT_EQ(grid.cell_of(std::array<double, 2>{2.5, 2.5}), 3u + 4u * 2u);
  EXPECT_EQ(grid.cell_of(std::array<double, 2>{0.0, 1.0}), 1u + 4u * 1u);  // on a boundary: the upper cell
  EXPECT_EQ(grid.cell_of(std::array<double, 2>{-7.0, 1e300}), 0u + 4u * 2u);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(grid.cell_of(std::array<double, 2>{nan, nan}), 0u);
}

// Every cell whose coordinates differ from home's by at most one along each
// axis, counting across the ends of a wrapping axis.
std::set<std::size_t> brute_force_block(const std::array<int, 3>& cells, const std::array<bool, 3>& wraps,
                                        std::size_t home) {
  const auto coordinate = [&](std::size_t c, int a) {
    std::size_t stride = 1;
    for (int b = 0; b < a; ++b) stride *= static_cast<std::size_t>(cells[b]);
    return static_cast<int>(c / stride % static_cast<std::size_t>(cells[a]));
  };
  std::set<std::size_t> block;
  const std::size_t total = static_cast<std::size_t>(cells[0] * cells[1] * cells[2]);
  for (std::size_t c = 0; c < total; ++c) {
    bool near = true;
    for (int a = 0; a < 3; ++a) {
      int d = std::abs(coordinate(c, a) - coordinate(home, a));
      if (wraps[a]) d = std::min(d, cells[a] - d);
      near &= d <= 1;
    }
    if (near) block.insert(c);
  }
  return block;
}

TEST(CellGrid, TheBlockAroundACellIsEachNeighbourOnceInAxisOrder) {
  for (const std::array<int, 3> cells : {std::array<int, 3>{5, 4, 3}, {1, 2, 6}, {3, 1, 2}}) {
    for (const std::array<bool, 3> wraps : {std::array<bool, 3>{true, true, true}, {false, false, false},
                                           {true, false, true}}) {
      const CellGrid<3> grid({}, {1.0, 1.0, 1.0}, cells, wraps);
      for (std::size_t home = 0; home < grid.cell_count(); ++home) {
        std::vector<std::size_t> visited;
        grid.for_each_neighbour(home, [&](std::size_t c) { visited.push_back(c); });
        const std::set<std::size_t> distinct(visited.begin(), visited.end());
        ASSERT_EQ(distinct.size(), visited.size()) << "a cell visited twice around " << home;
        EXPECT_EQ(distinct, brute_force_block(cells, wraps, home)) << "home " << home;
      }
    }
  }
}

TEST(CellGrid, NeighboursComeFirstAxisFastest) {
  const CellGrid<2> grid({}, {3.0, 3.0}, {3, 3}, {false, false});
  std::vector<std::size_t> visited;
  grid.for_each_neighbour(4, [&](std::size_t c) { visited.push_back(c); });  // the middle cell
  EXPECT_EQ(visited, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
}

}  // namespace
}  // namespace granflow
