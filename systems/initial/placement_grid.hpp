#pragma once
// The cell lists that placing particles needs: cells over a region at least
// the largest contact distance wide, so that every particle a point can
// touch lies in the cells around it. Random sequential addition asks whether
// a trial position touches anything; compression walks each particle's
// neighbours to push overlapping pairs apart.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "components/box.hpp"
#include "components/vector.hpp"

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

template <int D>
class PlacementGrid {
 public:
  // Along periodic axes of the box that the region spans fully, the cells
  // wrap around; elsewhere the region ends.
  PlacementGrid(const Box<D>& box, const PlacementRegion<D>& region, double contact, std::size_t count)
      : lower_(region.lower), wraps_(wrapping_axes(box, region)) {
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) {
      const double extent = region.upper[a] - region.lower[a];
      cells_[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(extent / contact));
      // A few cells per particle at most, however small the particles.
      while (total * static_cast<std::size_t>(cells_[a]) > 4 * count + 64 && cells_[a] > 1) cells_[a] /= 2;
      width_[a] = extent / static_cast<double>(cells_[a]);
      total *= static_cast<std::size_t>(cells_[a]);
      reach_[a] = static_cast<std::int64_t>(std::ceil(contact / width_[a]));
    }
    head_.assign(total, -1);
    next_.assign(count, -1);
  }

  const std::array<bool, D>& wraps() const { return wraps_; }

  void clear() { std::fill(head_.begin(), head_.end(), -1); }

  void insert(std::size_t i, const Vec<D>& x) {
    const std::size_t k = linear(coordinates(x));
    next_[i] = head_[k];
    head_[k] = static_cast<std::int64_t>(i);
  }

  // Calls visit(k) for each particle k in the cells within contact distance
  // of x (where the grid has fewer cells along a wrapping axis than that
  // reach spans, a cell comes more than once), until visit returns true;
  // returns whether one did.
  template <class Visit>
  bool any_near(const Vec<D>& x, Visit visit) const {
    const auto c = coordinates(x);
    std::array<std::int64_t, D> o{};
    for (int a = 0; a < D; ++a) o[a] = -reach_[a];
    while (true) {
      std::array<std::int64_t, D> n{};
      bool inside = true;
      for (int a = 0; a < D; ++a) {
        n[a] = c[a] + o[a];
        if (n[a] < 0 || n[a] >= cells_[a]) {
          if (!wraps_[a]) inside = false;
          n[a] = ((n[a] % cells_[a]) + cells_[a]) % cells_[a];
        }
      }
      if (inside)
        for (std::int64_t k = head_[linear(n)]; k >= 0; k = next_[static_cast<std::size_t>(k)])
          if (visit(static_cast<std::size_t>(k))) return true;
      int a = 0;
      for (; a < D; ++a) {
        if (++o[a] <= reach_[a]) break;
        o[a] = -reach_[a];
      }
      if (a == D) return false;
    }
  }

 private:
  std::array<std::int64_t, D> coordinates(const Vec<D>& x) const {
    std::array<std::int64_t, D> c{};
    for (int a = 0; a < D; ++a)
      c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>((x[a] - lower_[a]) / width_[a]), 0, cells_[a] - 1);
    return c;
  }
  std::size_t linear(const std::array<std::int64_t, D>& c) const {
    std::size_t k = 0;
    for (int a = D - 1; a >= 0; --a) k = k * static_cast<std::size_t>(cells_[a]) + static_cast<std::size_t>(c[a]);
    return k;
  }

  std::array<double, D> lower_{};
  std::array<bool, D> wraps_{};
  std::array<std::int64_t, D> cells_{};
  std::array<double, D> width_{};
  std::array<std::int64_t, D> reach_{};
  std::vector<std::int64_t> head_, next_;
};

}  // namespace granflow
