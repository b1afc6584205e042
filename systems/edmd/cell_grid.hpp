#pragma once
// Cell list for event-driven dynamics: cells at least one contact distance
// wide, so a particle can only touch particles in its own and adjacent cells
// until it crosses into another cell (a scheduled event). Membership is an
// intrusive singly linked list per cell; cells hold about one particle, so
// unlinking by a short walk is cheaper than storing back links.
//
// The grid has one layer of halo cells around the box, so every cell's 3^D
// neighbours are fixed offsets in memory and no prediction wraps indices.
// Across a periodic face a halo cell shares the list of the cell it images
// (its head is kept equal to that cell's head); across a wall it stays empty.
// A halo cell's particles are seen shifted by one box length (shift_offset()).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "components/box.hpp"
#include "components/vector.hpp"
#include "engine/core/page_release.hpp"
#include "systems/edmd/occupied_cells.hpp"

namespace granflow::edmd {

template <int D>
class CellGrid {
 public:
  static constexpr int neighbour_count = D == 2 ? 9 : 27;
  // Offset lists are padded with zeros to whole groups for occupied_cells().
  static constexpr std::size_t padded(int count) {
    return static_cast<std::size_t>((count + occupancy_group - 1) / occupancy_group * occupancy_group);
  }
  // Shift slot of a neighbour on the same side of every periodic face.
  static constexpr std::uint8_t unshifted = (neighbour_count - 1) / 2;
  static constexpr std::int32_t unshifted_offset = D * unshifted;
  // Memory bound: at most this many cells (4 bytes each) per particle.
  static constexpr std::size_t max_cells_per_particle = 3;
  using Coordinates = std::array<std::int32_t, D>;

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
      for (int a = 0; a < D; ++a) {
        count_[a] = std::max(1, static_cast<std::int32_t>(std::floor(count_[a] / factor)));
        width_[a] = box.length[a] / count_[a];
      }
    }
    std::size_t padded_total = 1;
    for (int a = 0; a < D; ++a) {
      periodic_[a] = box.periodic[a];
      length_[a] = box.length[a];
      stride_[a] = static_cast<std::int32_t>(padded_total);
      padded_total *= static_cast<std::size_t>(count_[a] + 2);
    }
    // Linear offsets of the 3^D neighbours, first axis fastest.
    for (int n = 0; n < neighbour_count; ++n) {
      std::int32_t offset = 0, rest = n;
      for (int a = 0; a < D; ++a) {
        offset += (rest % 3 - 1) * stride_[a];
        rest /= 3;
      }
      neighbour_offset_[static_cast<std::size_t>(n)] = offset;
    }
    for (int slot = 0; slot < neighbour_count; ++slot)
      for (int a = 0, rest = slot; a < D; ++a, rest /= 3)
        shift_[static_cast<std::size_t>(D * slot + a)] = (rest % 3 - 1) * length_[a];
    // A halo cell beyond a periodic face shows the cell it images one box
    // length away, whoever looks at it.
    // A cell inside the box on a periodic face is marked: its list is
    // mirrored into halo cells whenever its head changes.
    shift_slot_.assign(padded_total, unshifted);
    for (std::size_t cell = 0; cell < padded_total; ++cell) {
      int slot = 0;
      bool imaged = false;
      for (int a = D - 1, weight = neighbour_count / 3; a >= 0; --a, weight /= 3) {
        const auto padded = static_cast<std::int32_t>(cell / static_cast<std::size_t>(stride_[a])) % (count_[a] + 2);
        const int side = !periodic_[a] ? 0 : padded == 0 ? -1 : padded == count_[a] + 1 ? 1 : 0;
        slot += (side + 1) * weight;
        imaged = imaged || (periodic_[a] && (padded == 1 || padded == count_[a]));
      }
      shift_slot_[cell] = static_cast<std::uint8_t>(slot | (imaged ? imaged_bit : 0));
    }
    build_walks();
    head_.assign(padded_total, -1);
    member_.assign(particle_count, Membership{-1, 0});
  }

  // Empties every cell, keeping the geometry.
  void clear() { std::fill(head_.begin(), head_.end(), -1); }
  // Releases the memory of the cell lists (see release_pages()); only
  // clear() and insertions may follow.
  void release_lists() const {
    release_pages(head_);
    release_pages(member_);
  }

  std::int32_t count(int axis) const { return count_[axis]; }
  double width(int axis) const { return width_[axis]; }
  // Step in the linear index of a cell to its neighbour along `axis`.
  std::int32_t stride(int axis) const { return stride_[axis]; }
  // Cells inside the box (halo cells not counted).
  std::size_t cell_total() const {
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) total *= static_cast<std::size_t>(count_[a]);
    return total;
  }
  std::uint32_t cell_of(std::uint32_t i) const { return member_[i].cell; }
  std::int32_t head(std::uint32_t cell) const { return head_[cell]; }
  const std::int32_t* heads() const { return head_.data(); }
  std::int32_t next(std::uint32_t i) const { return member_[i].next; }
  const void* membership(std::uint32_t i) const { return &member_[i]; }
  // The offsets of the neighbour_count cells around a cell (itself included), padded.
  const std::int32_t* neighbour_offsets() const { return neighbour_offset_.data(); }
  // Where a particle listed in `cell` is seen from the box's neighbouring
  // cells: the D components at this offset of shift_table().
  std::int32_t shift_offset(std::uint32_t cell) const { return D * (shift_slot_[cell] & ~imaged_bit); }
  const double* shift_table() const { return shift_.data(); }
  // Whether some neighbour of a cell inside the box lies across a periodic
  // face (the cell is on that face), so that its neighbours need shifts.
  bool sees_images(std::uint32_t cell) const { return (shift_slot_[cell] & imaged_bit) != 0; }

  // The cells to scan after a crossing through `face` (2 axis + upward):
  // those that have just become adjacent, as offsets from the new cell
  // (entered_count of them, padded).
  static constexpr int entered_count = neighbour_count / 3;
  const std::int32_t* entered_cells(int face) const { return entered_[static_cast<std::size_t>(face)].data(); }

  // The neighbourhoods of two adjacent cells, the first at offset `delta`
  // (each component -1, 0 or 1) from the second, as offsets from the first:
  // the cells only the first sees, then those both see, then those only the
  // second sees. Empty (no cells) when the two are not adjacent.
  struct PairWalk {
    std::array<std::int32_t, padded(2 * neighbour_count)> offsets;
    int first_only;  // cells [0, first_only) belong to the first only
    int shared_end;  // cells [first_only, shared_end) to both, [shared_end, total) to the second
    int total;
  };
  const PairWalk& pair_walk(const Coordinates& first, const Coordinates& second) const {
    int code = 0;
    for (int a = D - 1; a >= 0; --a) {
      const std::int32_t delta = first[a] - second[a];
      if (delta < -1 || delta > 1) return no_walk_;
      code = 3 * code + delta + 1;
    }
    return walks_[static_cast<std::size_t>(code)];
  }

  // Coordinates inside the box (0 .. count - 1) of a cell inside the box.
  Coordinates coordinates(std::uint32_t cell) const {
    Coordinates c{};
    for (int a = D - 1; a > 0; --a) {
      const auto stride = static_cast<std::uint32_t>(stride_[a]);
      c[a] = static_cast<std::int32_t>(cell / stride) - 1;
      cell %= stride;
    }
    c[0] = static_cast<std::int32_t>(cell) - 1;  // the first axis has stride 1
    return c;
  }
  std::uint32_t linear(const Coordinates& c) const {
    std::int32_t cell = 0;
    for (int a = 0; a < D; ++a) cell += (c[a] + 1) * stride_[a];
    return static_cast<std::uint32_t>(cell);
  }

  // Cell containing a position inside the box.
  std::uint32_t locate(const auto& x) const { return linear(locate_coordinates(x)); }
  Coordinates locate_coordinates(const auto& x) const {
    Coordinates c{};
    for (int a = 0; a < D; ++a)
      c[a] = std::clamp(static_cast<std::int32_t>(std::floor(x[a] / width_[a])), 0, count_[a] - 1);
    return c;
  }

  // A cell's position in row order over the cells inside the box, which does
  // not depend on the halo (for saved states), and back.
  std::uint64_t serial(std::uint32_t cell) const {
    const Coordinates c = coordinates(cell);
    std::uint64_t index = 0;
    for (int a = D - 1; a >= 0; --a) index = index * static_cast<std::uint64_t>(count_[a]) + static_cast<std::uint64_t>(c[a]);
    return index;
  }
  std::uint32_t from_serial(std::uint64_t index) const {
    Coordinates c{};
    for (int a = 0; a < D; ++a) {
      c[a] = static_cast<std::int32_t>(index % static_cast<std::uint64_t>(count_[a]));
      index /= static_cast<std::uint64_t>(count_[a]);
    }
    return linear(c);
  }

  void insert(std::uint32_t i, std::uint32_t cell) {
    member_[i].cell = cell;
    member_[i].next = head_[cell];
    head_[cell] = static_cast<std::int32_t>(i);
    mirror(cell);
  }

  void erase(std::uint32_t i) {
    const std::uint32_t cell = member_[i].cell;
    std::int32_t* link = &head_[cell];
    if (*link == static_cast<std::int32_t>(i)) {
      *link = member_[i].next;
      mirror(cell);
      return;
    }
    while (*link != static_cast<std::int32_t>(i)) link = &member_[static_cast<std::size_t>(*link)].next;
    *link = member_[i].next;
  }

  std::size_t bytes_per_particle() const {
    const std::size_t count = std::max<std::size_t>(member_.size(), 1);
    return sizeof(Membership) + head_.size() * (sizeof(std::int32_t) + sizeof(std::uint8_t)) / count;
  }

 private:
  void build_walks() {
    const auto digit = [](int n, int a) {
      for (int k = 0; k < a; ++k) n /= 3;
      return n % 3 - 1;
    };
    for (int face = 0; face < 2 * D; ++face) {
      int used = 0;
      for (int n = 0; n < neighbour_count; ++n)
        if (digit(n, face / 2) == (face % 2 == 1 ? 1 : -1))
          entered_[static_cast<std::size_t>(face)][static_cast<std::size_t>(used++)] = neighbour_offset_[static_cast<std::size_t>(n)];
    }
    no_walk_ = PairWalk{{}, 0, 0, 0};
    for (int d = 0; d < neighbour_count; ++d) {
      PairWalk& walk = walks_[static_cast<std::size_t>(d)];
      walk.offsets.fill(0);
      const auto within = [&](int n, int sign) {
        bool inside = true;
        for (int a = 0; a < D; ++a) inside = inside && std::abs(digit(d, a) + sign * digit(n, a)) <= 1;
        return inside;
      };
      const std::int32_t delta = neighbour_offset_[static_cast<std::size_t>(d)];
      int used = 0;
      for (int n = 0; n < neighbour_count; ++n)
        if (!within(n, 1)) walk.offsets[static_cast<std::size_t>(used++)] = neighbour_offset_[static_cast<std::size_t>(n)];
      walk.first_only = used;
      for (int n = 0; n < neighbour_count; ++n)
        if (within(n, 1)) walk.offsets[static_cast<std::size_t>(used++)] = neighbour_offset_[static_cast<std::size_t>(n)];
      walk.shared_end = used;
      // The second cell's neighbour m lies at m - delta from the first; the
      // shared ones are listed already.
      for (int m = 0; m < neighbour_count; ++m)
        if (!within(m, -1)) walk.offsets[static_cast<std::size_t>(used++)] = neighbour_offset_[static_cast<std::size_t>(m)] - delta;
      walk.total = used;
    }
  }

  // Copies a face cell's head into the halo cells that image it. Most cells
  // are not on a face: their test stays inline, the copy is a call.
  void mirror(std::uint32_t cell) {
    if (sees_images(cell)) mirror_into_halo(cell);
  }
  [[gnu::noinline]] void mirror_into_halo(std::uint32_t cell) {
    const Coordinates c = coordinates(cell);
    // Per axis, the padded coordinates at which this cell appears: its own,
    // and the halo layer beyond the opposite periodic face (both for a
    // single-cell axis).
    std::array<std::array<std::int32_t, 3>, D> at{};
    std::array<int, D> choices{};
    for (int a = 0; a < D; ++a) {
      at[a][0] = c[a] + 1;
      choices[a] = 1;
      if (periodic_[a] && c[a] == 0) at[a][choices[a]++] = count_[a] + 1;
      if (periodic_[a] && c[a] == count_[a] - 1) at[a][choices[a]++] = 0;
    }
    std::array<int, D> pick{};
    while (true) {
      int a = 0;
      for (; a < D; ++a) {
        if (++pick[a] < choices[a]) break;
        pick[a] = 0;
      }
      if (a == D) break;
      std::int32_t image = 0;
      for (int b = 0; b < D; ++b) image += at[b][pick[b]] * stride_[b];
      head_[static_cast<std::size_t>(image)] = head_[cell];
    }
  }

  std::array<std::int32_t, D> count_{};
  std::array<std::int32_t, D> stride_{};  // of the grid with its halo
  std::array<bool, D> periodic_{};
  std::array<double, D> length_{};
  std::array<std::int32_t, padded(neighbour_count)> neighbour_offset_{};
  std::array<double, D * neighbour_count> shift_{};
  // Per cell of the grid with its halo: the slot of its shift, plus
  // imaged_bit on a cell inside the box on a periodic face (halo cells image
  // it, and it sees them).
  static constexpr std::uint8_t imaged_bit = 0x80;
  std::vector<std::uint8_t> shift_slot_;
  std::array<std::array<std::int32_t, padded(neighbour_count / 3)>, 2 * D> entered_{};
  std::array<PairWalk, neighbour_count> walks_{};
  PairWalk no_walk_{};
  std::array<double, D> width_{};
  std::vector<std::int32_t> head_;
  struct Membership {
    std::int32_t next;  // next particle in the same cell, -1 at the end
    std::uint32_t cell;
  };
  std::vector<Membership> member_;
};

}  // namespace granflow::edmd
