#pragma once
// A grid of cells over a rectangular region, the geometry that DEM's
// neighbour lists and the placement of particles share: the cell of a point,
// and the cells around a cell (the 3^D block, wrapped along periodic axes and
// cut at the region's edges elsewhere). How many cells each axis gets is the
// caller's choice (a contact range, a memory bound); binning the particles
// into the cells is count_scan_fill's (counting_sort.hpp) where a whole set
// is binned at once.

#include <array>
#include <cmath>
#include <cstddef>

namespace granflow {

template <int D>
class CellGrid {
 public:
  CellGrid() = default;
  // `cells[a]` cells along axis a over [lower[a], lower[a] + extent[a]);
  // along an axis that `wraps`, the last cell neighbours the first.
  CellGrid(const std::array<double, D>& lower, const std::array<double, D>& extent, const std::array<int, D>& cells,
           const std::array<bool, D>& wraps)
      : lower_(lower), cells_(cells), wraps_(wraps) {
    for (int a = 0; a < D; ++a) {
      stride_[a] = count_;
      per_length_[a] = cells[a] / extent[a];
      count_ *= static_cast<std::size_t>(cells[a]);
    }
  }

  std::size_t cell_count() const { return count_; }
  int cells(int axis) const { return cells_[axis]; }
  std::size_t stride(int axis) const { return stride_[axis]; }

  // The cell of a point; one outside the region (or not finite) lands in
  // the nearest edge cell.
  template <class Point>
  std::size_t cell_of(const Point& x) const {
    std::size_t c = 0;
    for (int a = 0; a < D; ++a) {
      // In double first: a point far outside must not overflow the integer.
      const double s = std::floor((x[a] - lower_[a]) * per_length_[a]);
      const int q = s > 0.0 ? static_cast<int>(std::fmin(s, static_cast<double>(cells_[a] - 1))) : 0;
      c += stride_[a] * static_cast<std::size_t>(q);
    }
    return c;
  }

  // Calls visit(cell) for each distinct cell of the block around `home`,
  // the first axis fastest, offsets -1, 0, +1 along each.
  template <class Visit>
  void for_each_neighbour(std::size_t home, Visit&& visit) const {
    std::array<std::array<std::size_t, 3>, D> term{};
    std::array<int, D> count{};
    for (int a = 0; a < D; ++a) {
      const int h = static_cast<int>(home / stride_[a] % static_cast<std::size_t>(cells_[a]));
      for (int o = -1; o <= 1; ++o) {
        int q = h + o;
        if (q < 0 || q >= cells_[a]) {
          if (!wraps_[a]) continue;
          q = (q + cells_[a]) % cells_[a];
        }
        const std::size_t t = stride_[a] * static_cast<std::size_t>(q);
        bool seen = false;  // an axis of one or two wrapped cells reaches a cell twice
        for (int k = 0; k < count[a]; ++k) seen |= term[a][k] == t;
        if (!seen) term[a][count[a]++] = t;
      }
    }
    if constexpr (D == 1) {
      for (int i = 0; i < count[0]; ++i) visit(term[0][i]);
    } else if constexpr (D == 2) {
      for (int j = 0; j < count[1]; ++j)
        for (int i = 0; i < count[0]; ++i) visit(term[1][j] + term[0][i]);
    } else {
      for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
          for (int i = 0; i < count[0]; ++i) visit(term[2][k] + term[1][j] + term[0][i]);
    }
  }

 private:
  std::array<double, D> lower_{};
  std::array<int, D> cells_{};
  std::array<bool, D> wraps_{};
  std::array<std::size_t, D> stride_{};
  std::array<double, D> per_length_{};
  std::size_t count_ = 1;
};

}  // namespace granflow
