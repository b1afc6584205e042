#pragma once
// Cell list for event-driven dynamics: cells at least one contact distance
// wide, so a particle can only touch particles in its own and adjacent cells
// until it crosses into another cell (a scheduled event). Membership is an
// intrusive singly linked list per cell; cells hold about one particle, so
// unlinking by a short walk is cheaper than storing back links.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "components/box.hpp"

namespace granflow::edmd {

template <int D>
class CellGrid {
 public:
  static constexpr int neighbour_count = D == 2 ? 9 : 27;
  // Memory bound: at most this many cells (4 bytes each) per particle.
  static constexpr std::size_t max_cells_per_particle = 3;

  CellGrid() = default;
  CellGrid(const Box<D>& box, double min_width, std::size_t particle_count) { reset(box, min_width, particle_count); }

  void reset(const Box<D>& box, double min_width, std::size_t particle_count) {
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) {
      // Cap the count so that huge boxes of few particles do not allocate
      // more cells than particles.
      const auto fit = static_cast<std::int64_t>(std::floor(box.length[a] / min_width));
      count_[a] = static_cast<std::int32_t>(std::clamp<std::int64_t>(fit, 1, 1 << 20));
      width_[a] = box.length[a] / count_[a];
      total *= static_cast<std::size_t>(count_[a]);
    }
    // Dilute gases would otherwise get many empty cells per particle; wider
    // cells cost a few more pair tests but save memory and cell crossings.
    const auto limit = static_cast<double>(std::max<std::size_t>(max_cells_per_particle * particle_count, 64));
    if (static_cast<double>(total) > limit) {
      const double shrink = std::cbrt(static_cast<double>(total) / limit);
      const double factor = D == 3 ? shrink : std::sqrt(shrink * shrink * shrink);
      total = 1;
      for (int a = 0; a < D; ++a) {
        count_[a] = std::max(1, static_cast<std::int32_t>(std::floor(count_[a] / factor)));
        width_[a] = box.length[a] / count_[a];
        total *= static_cast<std::size_t>(count_[a]);
      }
    }
    stride_[0] = 1;
    for (int a = 1; a < D; ++a) stride_[a] = stride_[a - 1] * count_[a - 1];
    // Linear offsets of the 3^D neighbours, first axis fastest.
    for (int n = 0; n < neighbour_count; ++n) {
      std::int32_t offset = 0, rest = n;
      for (int a = 0; a < D; ++a) {
        offset += (rest % 3 - 1) * stride_[a];
        rest /= 3;
      }
      neighbour_offset_[static_cast<std::size_t>(n)] = offset;
    }
    head_.assign(total, -1);
    member_.assign(particle_count, Membership{-1, 0});
  }

  // Empties every cell, keeping the geometry.
  void clear() {
    std::fill(head_.begin(), head_.end(), -1);
  }

  std::int32_t count(int axis) const { return count_[axis]; }
  double width(int axis) const { return width_[axis]; }
  std::size_t cell_total() const { return head_.size(); }
  std::uint32_t cell_of(std::uint32_t i) const { return member_[i].cell; }
  std::int32_t head(std::uint32_t cell) const { return head_[cell]; }
  void prefetch_cell(std::uint32_t cell) const { __builtin_prefetch(&head_[cell]); }
  std::int32_t next(std::uint32_t i) const { return member_[i].next; }

  std::array<std::int32_t, D> coordinates(std::uint32_t cell) const {
    std::array<std::int32_t, D> c{};
    for (int a = D - 1; a >= 0; --a) {
      c[a] = static_cast<std::int32_t>(cell / static_cast<std::uint32_t>(stride_[a]));
      cell -= static_cast<std::uint32_t>(c[a] * stride_[a]);
    }
    return c;
  }
  std::uint32_t linear(const std::array<std::int32_t, D>& c) const {
    std::int32_t cell = 0;
    for (int a = 0; a < D; ++a) cell += c[a] * stride_[a];
    return static_cast<std::uint32_t>(cell);
  }
  std::int32_t stride(int axis) const { return stride_[axis]; }
  std::int32_t neighbour_offset(int n) const { return neighbour_offset_[static_cast<std::size_t>(n)]; }

  // Cell containing a position inside the box.
  std::uint32_t locate(const auto& x) const {
    std::array<std::int32_t, D> c{};
    for (int a = 0; a < D; ++a)
      c[a] = std::clamp(static_cast<std::int32_t>(std::floor(x[a] / width_[a])), 0, count_[a] - 1);
    return linear(c);
  }

  void insert(std::uint32_t i, std::uint32_t cell) {
    member_[i].cell = cell;
    member_[i].next = head_[cell];
    head_[cell] = static_cast<std::int32_t>(i);
  }

  void erase(std::uint32_t i) {
    std::int32_t* link = &head_[member_[i].cell];
    while (*link != static_cast<std::int32_t>(i)) link = &member_[static_cast<std::size_t>(*link)].next;
    *link = member_[i].next;
  }

  std::size_t bytes_per_particle() const {
    const std::size_t count = std::max<std::size_t>(member_.size(), 1);
    return sizeof(Membership) + head_.size() * sizeof(std::int32_t) / count;
  }

 private:
  std::array<std::int32_t, D> count_{};
  std::array<std::int32_t, D> stride_{};
  std::array<std::int32_t, neighbour_count> neighbour_offset_{};
  std::array<double, D> width_{};
  std::vector<std::int32_t> head_;
  struct Membership {
    std::int32_t next;  // next particle in the same cell, -1 at the end
    std::uint32_t cell;
  };
  std::vector<Membership> member_;
};

}  // namespace granflow::edmd
