#pragma once
// Which SRD cell each particle is in, by counting sort: the cell of every
// particle (parallel), the number per cell, their prefix sum, then the
// particle indices cell by cell in index order (so the result does not
// depend on the thread count). Every `reorder_interval` steps the particle
// columns themselves are put in cell order (World::permute, which tells
// every listener), so that the cells' particles lie together in memory.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_cell_binning_description{
    "srd_cell_binning", "particles into the shifted SRD cells by counting sort; particle columns in cell order every k steps"};

template <int D>
class SrdCellBinning : public System {
 public:
  // reorder_interval: steps between reorderings of the particle columns (0: never).
  explicit SrdCellBinning(std::uint64_t reorder_interval) : reorder_interval_(reorder_interval) {}

  std::string name() const override { return "srd_cell_binning"; }
  Access access() const override {
    Access access;
    access.reads<Clock>().template writes<SrdCells<D>>();
    if (reorder_interval_ > 0) access.writes_every_component();
    else access.template reads<Position<D>>();
    return access;
  }

  void run(World& world) override {
    auto& cells = world.resource<SrdCells<D>>();
    bin(world, cells);
    const auto step = static_cast<std::uint64_t>(world.resource<Clock>().step);
    if (reorder_interval_ > 0 && step % reorder_interval_ == 0) {
      world.permute(cells.order);
      // Particle k is now the one that was order[k]: the cells follow.
      std::vector<std::uint32_t> moved(cells.cell.size());
      for (std::size_t k = 0; k < moved.size(); ++k) moved[k] = cells.cell[cells.order[k]];
      cells.cell.swap(moved);
      std::iota(cells.order.begin(), cells.order.end(), 0u);
    }
  }

  static void bin(const World& world, SrdCells<D>& cells) {
    const double* x = world.component<Position<D>>().data()->data();
    const std::size_t n = world.size();
    cells.cell.resize(n);
    cells.order.resize(n);
    std::uint32_t* cell = cells.cell.data();
    const double* shift = cells.shift.data();
    const double* length = cells.length.data();
    const std::int32_t* count = cells.cells.data();
    const Shear shear = cells.shear;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) cell[i] = cell_of<D>(x + D * i, shift, length, count, shear);
    });
    // Counting sort in a fixed number of chunks (not one per thread, so the
    // order is the same on any thread count): each chunk counts its particles
    // per cell, the counts give each chunk its place in every cell, and each
    // chunk then writes its particles there, in index order.
    const std::size_t cell_count = cells.cell_count();
    const std::size_t chunks = std::clamp<std::size_t>(n / (1u << 16), 1, 16);
    const std::size_t per_chunk = (n + chunks - 1) / chunks;
    cells.chunk_counts.assign(chunks * cell_count, 0u);
    std::uint32_t* counts = cells.chunk_counts.data();
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
      std::uint32_t* mine = counts + k * cell_count;
      for (std::size_t i = k * per_chunk; i < std::min(n, (k + 1) * per_chunk); ++i) ++mine[cell[i]];
    });
    // Exclusive prefix over (cell, chunk): chunk k of cell c starts after all
    // of cell c's earlier chunks.
    std::uint32_t running = 0;
    for (std::size_t c = 0; c < cell_count; ++c) {
      cells.start[c] = running;
      for (std::size_t k = 0; k < chunks; ++k) {
        const std::uint32_t here = counts[k * cell_count + c];
        counts[k * cell_count + c] = running;
        running += here;
      }
    }
    cells.start[cell_count] = running;
    std::uint32_t* order = cells.order.data();
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
      std::uint32_t* next = counts + k * cell_count;
      for (std::size_t i = k * per_chunk; i < std::min(n, (k + 1) * per_chunk); ++i)
        order[next[cell[i]]++] = static_cast<std::uint32_t>(i);
    });
  }

 private:
  std::uint64_t reorder_interval_;
};

}  // namespace granflow::srd
