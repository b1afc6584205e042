#pragma once
// The binning of particles into cells that SRD and DEM share: a stable
// counting sort (count, exclusive scan, fill). Items keep their index order
// within a cell, and the work is split into a fixed number of chunks (not
// one per thread), so the order is the same on any thread count.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace granflow {

// `cell[i] < cell_count` for the `n` items. Writes start[0 .. cell_count]
// (where each cell's items begin; start[cell_count] = n) and order[0 .. n)
// (the items cell by cell, in index order within a cell); `count`, if given,
// gets each cell's number of items. `scratch` holds the chunks' counts.
inline void count_scan_fill(const std::uint32_t* cell, std::size_t n, std::size_t cell_count, std::uint32_t* start,
                            std::uint32_t* order, std::vector<std::uint32_t>& scratch, std::uint32_t* count = nullptr) {
  // Chunks of at least 2^16 items, and no more than keep the scratch within
  // twice the items (a sparse grid, as DEM's in a tall empty box, has many
  // more cells than spheres). The order does not depend on the chunking.
  const std::size_t chunks =
      std::clamp<std::size_t>(std::min(n / (1u << 16), 2 * n / std::max<std::size_t>(cell_count, 1)), 1, 16);
  const std::size_t per_chunk = (n + chunks - 1) / chunks;
  scratch.assign(chunks * cell_count, 0u);
  std::uint32_t* counts = scratch.data();
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
    std::uint32_t* mine = counts + k * cell_count;
    for (std::size_t i = k * per_chunk; i < std::min(n, (k + 1) * per_chunk); ++i) ++mine[cell[i]];
  });
  // Exclusive prefix over (cell, chunk): chunk k of cell c starts after all
  // of cell c's earlier chunks. The cells' totals, their prefix sum, then
  // each cell's chunks, in parallel but for the plain sum over cells.
  tbb::parallel_for(std::size_t{0}, cell_count, [&](std::size_t c) {
    std::uint32_t total = 0;
    for (std::size_t k = 0; k < chunks; ++k) total += counts[k * cell_count + c];
    start[c + 1] = total;
    if (count) count[c] = total;
  });
  start[0] = 0;
  for (std::size_t c = 0; c < cell_count; ++c) start[c + 1] += start[c];
  tbb::parallel_for(std::size_t{0}, cell_count, [&](std::size_t c) {
    std::uint32_t next = start[c];
    for (std::size_t k = 0; k < chunks; ++k) {
      const std::uint32_t here = counts[k * cell_count + c];
      counts[k * cell_count + c] = next;
      next += here;
    }
  });
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
    std::uint32_t* next = counts + k * cell_count;
    for (std::size_t i = k * per_chunk; i < std::min(n, (k + 1) * per_chunk); ++i)
      order[next[cell[i]]++] = static_cast<std::uint32_t>(i);
  });
}

}  // namespace granflow
