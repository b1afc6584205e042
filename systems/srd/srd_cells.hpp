#pragma once
// The SRD collision grid of one World (a resource): cells of edge 1 filling
// the box, this step's random shift, the Lees-Edwards state, which cell each
// particle is in, and per cell its particle count, mass, mean velocity V and
// temperature theta. Everything here is rebuilt every step from the
// particles and the step's random numbers, so a checkpoint needs none of it.
//
// The particles are not sorted every step: they are kept in cell order by a
// counting sort every few steps, and in between each fixed block of
// consecutive particles records the (circular) range of cells it touches.
// A task that owns a range of cells then reads only the blocks that reach
// into it, and sums each cell's particles in storage order, so the cell sums
// do not depend on how the cells are split over threads.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "components/vector.hpp"
#include "systems/srd/srd_cell_kernels.hpp"
#include "systems/srd/srd_kernels.hpp"
#include "systems/srd/srd_walls.hpp"

namespace granflow::srd {

// The cells of one block of particles: first, first + 1, ..., first + span,
// modulo the cell count.
struct BlockCells {
  std::uint32_t first = 0;
  std::uint32_t span = 0;

  // Whether any of them lies in [begin, end).
  bool meets(std::uint32_t begin, std::uint32_t end, std::uint32_t cell_count) const {
    if (span + 1 >= cell_count) return true;
    const std::uint64_t last = static_cast<std::uint64_t>(first) + span;
    if (last < cell_count) return first < end && last >= begin;
    return first < end || last - cell_count >= begin;  // wraps past the last cell
  }
};

// Between reorderings a particle's cell record is rarely in cache: it is
// fetched this many particles ahead, so that the misses overlap.
inline constexpr std::size_t prefetch_distance = 16;
template <class T>
inline void prefetch(const T* record) {
#if defined(__GNUC__)
  __builtin_prefetch(record);
  if constexpr (sizeof(T) > 64) __builtin_prefetch(reinterpret_cast<const char*>(record) + sizeof(T) - 1);
#endif
}

template <int D>
struct SrdCells {
  static constexpr const char* key = "srd_cells";
  static constexpr std::size_t block_size = 4096;  // particles per BlockCells

  std::array<std::int32_t, D> cells{};  // of the grid (along a bounded axis: with the layers beyond its walls)
  std::array<double, D> length{};       // of the periodic box
  std::array<double, D> origin{};       // where a bounded axis's first cell starts (0 when periodic)
  unsigned bounded = 0;                 // bit a: axis a ends at walls
  std::vector<Wall> walls;
  std::array<double, D> shift{};
  Shear shear;
  double particle_mass = 1.0;  // where the World has no Mass column
  // Whether the reduction sums each cell's first moment (for the collisional stress).
  bool record_moments = false;

  std::vector<std::uint32_t> cell;    // per particle
  std::vector<std::int8_t> image;     // per particle, with shear only: shear_image of its shifted position
  std::vector<BlockCells> blocks;     // per block of block_size particles
  // Counting sort (at reorderings, or on request): particle indices cell by
  // cell, cell c from start[c] to start[c + 1].
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> chunk_counts;  // its scratch: per chunk, per cell

  std::vector<std::uint32_t> count;  // per cell: particles
  std::vector<double> mass;          // per cell
  std::vector<Vec<D>> velocity;      // per cell: mean velocity V
  std::vector<double> theta;         // per cell: sum m |v - V|^2 / (D n)
  std::vector<CellSums<D>> sums;     // the reduction's scratch
  // Per cell, with record_moments: sum m (v - V) (y - y_cell), and the
  // reduction's scratch sum m (y - y_cell).
  std::vector<Vec<D>> moment;
  std::vector<double> moment_mass;
  // Per cell, this step's collisional transfer sum m dv_x (y - y_cell), for
  // the collisional stress; and how many cells had eps_eff <= 0.
  std::vector<double> transfer;
  std::uint64_t clamped_cells = 0;

  // Ghost particles (with walls): the mean particles per cell they fill a
  // cut cell up to, the seed and step their velocities are keyed by, and per
  // cell how many were added this step.
  double ghost_fill = 0.0;
  std::uint64_t seed = 0;
  std::vector<std::uint32_t> ghosts;
  std::uint64_t wall_reflections = 0;  // counted by the streaming, over the run

  // Energy bookkeeping, where record_energy is set: this step's kinetic
  // energy given by the walls' reflections (only moving walls give any), and
  // the kinetic energy the collisions changed, in cells without ghost
  // particles (the granular dissipation, negative) and in cells with them
  // (dissipation and the heat the ghosts exchange).
  bool record_energy = false;
  double step_wall_work = 0.0;
  double step_collision_energy = 0.0;
  double step_ghost_cell_energy = 0.0;
  // Where set (one rank's part of a system spread over ranks): per
  // particle, nonzero for a copy of another rank's particle, whose energy
  // change that rank books.
  const std::uint8_t* copies = nullptr;

  // cells_per_axis: the box; `box_walls` end the axes they are on, whose grid
  // then spans the walls' whole motion and one layer beyond.
  SrdCells(std::array<std::int32_t, D> cells_per_axis, std::size_t particles, std::vector<Wall> box_walls = {})
      : cells(cells_per_axis), walls(std::move(box_walls)) {
    for (int a = 0; a < D; ++a) length[a] = static_cast<double>(cells[a]);
    for (int a = 0; a < D; ++a) {
      double low = 0.0, high = 0.0;
      bool walled = false;
      for (const Wall& wall : walls) {
        if (wall.axis != a) continue;
        const double reach = std::abs(wall.amplitude);
        low = walled ? std::min(low, wall.rest - reach) : wall.rest - reach;
        high = walled ? std::max(high, wall.rest + reach) : wall.rest + reach;
        walled = true;
      }
      if (!walled) continue;
      origin[a] = std::floor(low) - 1.0;
      cells[a] = static_cast<std::int32_t>(std::ceil(high) + 1.0 - origin[a]);
      bounded |= 1u << a;
    }
    allocate_arrays(particles);
  }
  std::size_t cell_count() const { return mass.size(); }
  // The grid's per-cell arrays, zeroed, and the particles' cell indices.
  void allocate_arrays(std::size_t particles) {
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) total *= static_cast<std::size_t>(cells[a]);
    cell.resize(particles);
    start.assign(total + 1, 0);
    count.assign(total, 0);
    mass.assign(total, 0.0);
    velocity.assign(total, Vec<D>::Zero());
    theta.assign(total, 0.0);
    sums.resize(total);
    transfer.assign(total, 0.0);
    if (!walls.empty()) ghosts.assign(total, 0);
  }
  // Gives back the memory of every per-particle and per-cell array, keeping
  // the geometry: on a rank that holds the whole grid only to describe it
  // (allocate_arrays makes them again).
  void release_arrays() {
    const auto release = [](auto& values) { std::remove_reference_t<decltype(values)>().swap(values); };
    release(cell), release(image), release(blocks), release(order), release(start), release(chunk_counts);
    release(count), release(mass), release(velocity), release(theta), release(sums), release(moment);
    release(moment_mass), release(transfer), release(ghosts);
  }
  // The number cell c's random numbers are keyed by: c itself, or on one
  // rank's part of a grid spread over ranks (srd_domain_step.hpp), the cell
  // of the whole grid it is, so that every rank draws what one rank would.
  // The part differs from the whole only along `axis`, where its layer k is
  // the whole grid's layer (k + first) mod whole_cells.
  // The rank's own cells are those whose lower edge along `axis` lies in
  // [own_low, own_high) (its slab): each cell is one rank's, a straddling
  // one that of the rank below the boundary, which holds all its particles
  // while it reduces it.
  struct PartOfWhole {
    int axis = -1;  // -1: this grid is the whole grid
    std::int64_t first = 0;
    std::int64_t whole_cells = 0;
    std::int64_t own_low = 0, own_high = 0;
  };
  PartOfWhole part_of_whole;
  // Whether cell c is this part's own (every cell of the whole grid is): what
  // a sum over cells counts, so that the ranks' sums add to the whole's.
  bool owns(std::size_t c) const {
    const PartOfWhole& p = part_of_whole;
    if (p.axis < 0) return true;
    const double edge = origin[p.axis] + static_cast<double>(layer_of(c, p.axis)) - shift[p.axis];
    return edge >= static_cast<double>(p.own_low) && edge < static_cast<double>(p.own_high);
  }
  std::uint64_t cell_key(std::size_t c) const {
    const PartOfWhole& p = part_of_whole;
    if (p.axis < 0) return c;
    std::size_t stride = 1;
    for (int a = 0; a < p.axis; ++a) stride *= static_cast<std::size_t>(cells[a]);
    const auto along = static_cast<std::size_t>(cells[p.axis]);
    const std::size_t below = c % stride, layer = (c / stride) % along, above = c / (stride * along);
    const auto whole = static_cast<std::size_t>(p.whole_cells);
    const auto shifted = static_cast<std::int64_t>(layer) + p.first;
    const auto wrapped = static_cast<std::size_t>(((shifted % p.whole_cells) + p.whole_cells) % p.whole_cells);
    return below + stride * (wrapped + whole * above);
  }
  // Layer of cell c along `axis`.
  std::int64_t layer_of(std::size_t c, int axis) const {
    std::size_t stride = 1;
    for (int a = 0; a < axis; ++a) stride *= static_cast<std::size_t>(cells[a]);
    return static_cast<std::int64_t>((c / stride) % static_cast<std::size_t>(cells[axis]));
  }
  // Whether cell c of this step's shifted grid lies wholly between the walls
  // at `time` (true along axes without walls).
  bool inside_walls(std::size_t c, double time) const {
    std::size_t rest = c;
    double low[D], high[D];
    for (int a = 0; a < D; ++a) {
      const auto k = static_cast<double>(rest % static_cast<std::size_t>(cells[a]));
      rest /= static_cast<std::size_t>(cells[a]);
      low[a] = origin[a] + k - shift[a];
      high[a] = low[a] + 1.0;
    }
    for (const Wall& wall : walls) {
      const double at = wall.position(time);
      if (wall.side < 0 ? low[wall.axis] < at : high[wall.axis] > at) return false;
    }
    return true;
  }
  std::uint32_t particles_in(std::size_t c) const { return count[c]; }
  // The x velocity particle i's cell sees it move with beyond a shear plane.
  double image_velocity(std::size_t i) const { return image.empty() ? 0.0 : -image[i] * shear.velocity; }
};

}  // namespace granflow::srd
