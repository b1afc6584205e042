#pragma once
// The SRD collision grid of one World (a resource): cells of edge 1 filling
// the box, this step's random shift, the Lees-Edwards state, which cell each
// particle is in and the particles of each cell (counting sort: `order`
// lists particle indices cell by cell, cell c from start[c] to start[c+1]),
// and per cell its mass, mean velocity V and temperature theta. Everything
// here is rebuilt every step from the particles and the step's random
// numbers, so a checkpoint needs none of it.

#include <array>
#include <cstdint>
#include <vector>

#include "components/vector.hpp"
#include "systems/srd/srd_kernels.hpp"

namespace granflow::srd {

template <int D>
struct SrdCells {
  static constexpr const char* key = "srd_cells";

  std::array<std::int32_t, D> cells{};
  std::array<double, D> length{};
  std::array<double, D> shift{};
  Shear shear;
  double particle_mass = 1.0;  // where the World has no Mass column

  std::vector<std::uint32_t> cell;   // per particle
  std::vector<std::uint32_t> order;  // particle indices, cell by cell
  std::vector<std::uint32_t> start;  // per cell, and one past the last
  std::vector<std::uint32_t> chunk_counts;  // the binning's scratch: per chunk, per cell
  std::vector<double> mass;          // per cell
  std::vector<Vec<D>> velocity;      // per cell: mean velocity V
  std::vector<double> theta;         // per cell: sum m |v - V|^2 / (D n)
  // Per cell, this step's collisional transfer sum m dv_x (y - y_cell), for
  // the collisional stress; and how many cells had eps_eff <= 0.
  std::vector<double> transfer;
  std::uint64_t clamped_cells = 0;

  SrdCells(std::array<std::int32_t, D> cells_per_axis, std::size_t particles) : cells(cells_per_axis) {
    std::size_t count = 1;
    for (int a = 0; a < D; ++a) {
      length[a] = static_cast<double>(cells[a]);
      count *= static_cast<std::size_t>(cells[a]);
    }
    cell.resize(particles);
    order.resize(particles);
    start.assign(count + 1, 0);
    mass.assign(count, 0.0);
    velocity.assign(count, Vec<D>::Zero());
    theta.assign(count, 0.0);
    transfer.assign(count, 0.0);
  }
  std::size_t cell_count() const { return mass.size(); }
  std::uint32_t particles_in(std::size_t c) const { return start[c + 1] - start[c]; }
};

}  // namespace granflow::srd
