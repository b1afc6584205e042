#pragma once
// Which SRD cell each particle is in, every step: the cell of every particle
// and, per block of consecutive particles, the range of cells the block
// touches (srd_cells.hpp says why). Every `reorder_interval` steps the
// particle columns are put in cell order by a counting sort (count, prefix
// sum, fill; in a fixed number of chunks, so the order does not depend on
// the thread count) and World::permute, which tells every listener: then
// each block touches few cells and a cell's particles lie together in
// memory. Sorting every step would move all particle data every step, for
// locality that the few steps in between barely lose.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/geometry/counting_sort.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_cell_binning_description{
    "srd_cell_binning", "the shifted SRD cell of every particle; particle columns in cell order every k steps (counting sort)"};

// The default steps between reorderings for particles that move `free_path`
// cells per step along each axis (sqrt(kT/m) dt): locality is lost once they
// have moved a few cells, and a reordering costs about five steps' binning.
inline std::uint64_t reorder_interval_for(double free_path) {
  if (!(free_path > 0.0)) return 100;
  return static_cast<std::uint64_t>(std::clamp(std::llround(2.0 / free_path), 5ll, 100ll));
}

// Declared as reordering the particles whether or not this run's interval
// is 0 (never): the wider declaration only orders systems, it changes no result.
template <int D>
class SrdCellBinning : public SystemOf<Reads<Clock>, Writes<SrdCells<D>, EveryColumn>> {
 public:
  using View = typename SystemOf<Reads<Clock>, Writes<SrdCells<D>, EveryColumn>>::View;
  using SortView = granflow::View<Reads<>, Writes<EveryColumn>>;
  // reorder_interval: steps between reorderings of the particle columns (0: never).
  explicit SrdCellBinning(std::uint64_t reorder_interval) : reorder_interval_(reorder_interval) {}

  std::string name() const override { return "srd_cell_binning"; }

  void run_on(View view) override {
    auto& cells = view.template write<SrdCells<D>>();
    const auto step = static_cast<std::uint64_t>(view.template read<Clock>().step);
    if (reorder_interval_ > 0 && step % reorder_interval_ == 0) sort(view, cells);
    else assign(view.template read<Position<D>>(), cells);
  }

  // The cell of every particle and the cells of every block; from particle
  // `first` on where those before it are assigned already (a step over
  // ranks assigns its own particles while the neighbours' travel).
  static void assign(const Position<D>& position, SrdCells<D>& cells, std::size_t first = 0) {
    const double* x = position.data()->data();
    const std::size_t n = position.size();
    cells.cell.resize(n);
    cells.image.resize(D >= 2 && cells.shear.velocity != 0.0 ? n : 0);
    std::uint32_t* const cell_column = cells.cell.data();
    std::int8_t* const image_column = cells.image.empty() ? nullptr : cells.image.data();
    const SrdCells<D>& grid = cells;
    for_each_block(cells, n, first / SrdCells<D>::block_size, [&](std::size_t begin, std::size_t end) {
      // Local copies: the int8 stores may alias anything the lambda refers to.
      std::array<double, D> shift = grid.shift, length = grid.length, origin = grid.origin;
      std::array<std::int32_t, D> count = grid.cells;
      const Shear shear = grid.shear;
      const unsigned bounded = grid.bounded;
      std::uint32_t* cell = cell_column;
      std::int8_t* image = image_column;
      for (std::size_t i = begin; i < end; ++i) {
        cell[i] = cell_of<D>(x + D * i, shift.data(), length.data(), count.data(), shear, origin.data(), bounded);
        if (image) image[i] = static_cast<std::int8_t>(shear_image<D>(x + D * i, shift.data(), length.data()));
      }
    });
  }

  // assign, then the counting sort: `order` lists the particles cell by
  // cell in index order, `start` where each cell's list begins, and `count`
  // how many each cell holds.
  // Runs fill(begin, end) over every block of particles from `first_block`
  // on, in parallel, the block's cells being set in cells.cell by it; then
  // records each block's range of cells.
  template <class Fill>
  static void for_each_block(SrdCells<D>& cells, std::size_t n, std::size_t first_block, Fill&& fill) {
    const std::size_t block = SrdCells<D>::block_size;
    cells.blocks.resize((n + block - 1) / block);
    const auto cell_count = static_cast<std::int64_t>(cells.cell_count());
    tbb::parallel_for(std::min(first_block, cells.blocks.size()), cells.blocks.size(), [&](std::size_t b) {
      const std::size_t begin = b * block, end = std::min(n, begin + block);
      fill(begin, end);
      const std::uint32_t* cell = cells.cell.data();
      const std::int64_t first = cell[begin];
      std::int64_t low = 0, high = 0;
      for (std::size_t i = begin; i < end; ++i) {
        // Distance from the block's first cell, the short way round.
        std::int64_t d = static_cast<std::int64_t>(cell[i]) - first;
        if (2 * d > cell_count) d -= cell_count;
        if (2 * d <= -cell_count) d += cell_count;
        low = std::min(low, d);
        high = std::max(high, d);
      }
      cells.blocks[b] = {static_cast<std::uint32_t>((first + low + cell_count) % cell_count),
                         static_cast<std::uint32_t>(high - low)};
    });
  }

  static void bin(const Position<D>& position, SrdCells<D>& cells) {
    assign(position, cells);
    const std::size_t n = position.size();
    cells.order.resize(n);
    count_scan_fill(cells.cell.data(), n, cells.cell_count(), cells.start.data(), cells.order.data(), cells.chunk_counts,
                    cells.count.data());
  }

  // bin, then the particle columns in cell order: afterwards particle k is
  // the one that was order[k], and `order` is the identity.
  static void sort(SortView view, SrdCells<D>& cells) {
    bin(view.template read<Position<D>>(), cells);
    view.permute(cells.order);
    // The cells follow the particles, and the blocks the cells.
    const std::uint32_t* order = cells.order.data();
    // With the room the columns had, as World::permute keeps it.
    std::vector<std::uint32_t> cell;
    cell.reserve(cells.cell.capacity());
    cell.resize(cells.cell.size());
    std::vector<std::int8_t> image;
    image.reserve(cells.image.capacity());
    image.resize(cells.image.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cell.size(), 1u << 14), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        cell[k] = cells.cell[order[k]];
        if (!image.empty()) image[k] = cells.image[order[k]];
      }
    });
    cells.cell.swap(cell);
    cells.image.swap(image);
    for_each_block(cells, cells.cell.size(), 0, [](std::size_t, std::size_t) {});
    std::iota(cells.order.begin(), cells.order.end(), 0u);
  }

 private:
  std::uint64_t reorder_interval_;
};

}  // namespace granflow::srd
