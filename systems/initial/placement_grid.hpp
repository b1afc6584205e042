#pragma once
// The cell lists that placing particles needs: cells over a region at least
// the largest contact distance wide (systems/geometry/cell_grid.hpp), so
// that every particle a point can touch lies in the cells around it. Random
// sequential addition asks whether a trial position touches anything;
// compression walks each particle's neighbours to push overlapping pairs apart.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "components/box.hpp"
#include "components/vector.hpp"
#include "systems/geometry/cell_grid.hpp"

namespace granflow {

template <int D>
struct PlacementRegion {
  std::array<double, D> lower{};
  std::array<double, D> upper{};
};

// The periodic axes of the box that the region spans fully: particles
// placed there may cross the boundary.
template <int D>
std::array<bool, D> wrapping_axes(const Box<D>& box, const PlacementRegion<D>& region) {
  std::array<bool, D> wraps{};
  for (int a = 0; a < D; ++a)
    wraps[a] = box.periodic[a] && region.lower[a] <= 0.0 && region.upper[a] >= box.length[a];
  return wraps;
}

// Cell lists that grow as particles are placed: random sequential addition
// asks about a trial position before it places the next particle, so the
// cells are linked lists (a counting sort bins a finished set only).
template <int D>
class PlacementGrid {
 public:
  // Along periodic axes of the box that the region spans fully, the cells
  // wrap around; elsewhere the region ends. Cells are at least `contact`
  // wide, so the block of cells around a point holds everything it touches.
  PlacementGrid(const Box<D>& box, const PlacementRegion<D>& region, double contact, std::size_t count) {
    std::array<double, D> extent{};
    std::array<int, D> cells{};
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) {
      extent[a] = region.upper[a] - region.lower[a];
      std::int64_t n = std::max<std::int64_t>(1, static_cast<std::int64_t>(extent[a] / contact));
      // A few cells per particle at most, however small the particles.
      while (total * static_cast<std::size_t>(n) > 4 * count + 64 && n > 1) n /= 2;
      cells[a] = static_cast<int>(n);
      total *= static_cast<std::size_t>(n);
    }
    grid_ = CellGrid<D>(region.lower, extent, cells, wrapping_axes(box, region));
    head_.assign(grid_.cell_count(), -1);
    next_.assign(count, -1);
  }

  void clear() { std::fill(head_.begin(), head_.end(), -1); }

  void insert(std::size_t i, const Vec<D>& x) {
    const std::size_t k = grid_.cell_of(x);
    next_[i] = head_[k];
    head_[k] = static_cast<std::int64_t>(i);
  }

  // Calls visit(k) for each particle k in the cells around x, each once,
  // until visit returns true; returns whether one did.
  template <class Visit>
  bool any_near(const Vec<D>& x, Visit visit) const {
    bool found = false;
    grid_.for_each_neighbour(grid_.cell_of(x), [&](std::size_t cell) {
      for (std::int64_t k = head_[cell]; k >= 0 && !found; k = next_[static_cast<std::size_t>(k)])
        found = visit(static_cast<std::size_t>(k));
    });
    return found;
  }

 private:
  CellGrid<D> grid_;
  std::vector<std::int64_t> head_, next_;
};

}  // namespace granflow
