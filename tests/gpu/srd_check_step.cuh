#pragma once
// One cell's collision matrix and one particle's SRD step, as the GPU check
// runs them on the device and its test on the host: the same GRANFLOW_HD
// functions in the same order (tests/gpu/host_device_check.cuh says what each
// input means).

#include <cstdint>

#include "engine/core/host_device.hpp"
#include "systems/srd/srd_kernels.hpp"
#include "systems/srd/srd_walls.hpp"
#include "tests/gpu/host_device_check.cuh"

namespace granflow::cuda::srd {

GRANFLOW_HD inline void check_cell_matrix(const SrdCheckInput& in, std::uint64_t c, double* matrix) {
  granflow::srd::CellRotation<3> base;
  base.cos_alpha = in.cos_alpha;
  base.sin_alpha = in.sin_alpha;
  granflow::srd::CellRotation<3> r = granflow::srd::cell_rotation<3>(base, in.seed, in.step, c);
  r.eps = in.eps;
  r.matrix(matrix);
}

// Returns the particle's cell.
GRANFLOW_HD inline std::uint32_t check_particle_step(const SrdCheckInput& in, const double* matrices,
                                                     const double* means, double* x, double* v) {
  double length[3], origin[3] = {0.0, 0.0, 0.0};
  std::int32_t grid[3];
  for (int a = 0; a < 3; ++a) {
    length[a] = in.cells[a];
    grid[a] = in.cells[a];
  }
  unsigned bounded = 0;
  if (in.walls) {
    granflow::srd::Wall walls[2];
    for (int k = 0; k < 2; ++k) {
      walls[k].axis = 2;
      walls[k].side = k == 0 ? -1 : 1;
      walls[k].rest = k == 0 ? 0.0 : length[2];
    }
    const double g[3] = {0.0, 0.0, in.gravity};
    granflow::srd::stream_between_walls<3>(x, v, g, 0.0, in.dt, walls, 2);
    for (int a = 0; a < 2; ++a) x[a] = granflow::srd::wrapped(x[a], length[a]);
    origin[2] = -1.0;
    grid[2] = in.cells[2] + 2;
    bounded = 1u << 2;
  } else {
    granflow::srd::stream_particle<3>(x, v, in.dt, length, granflow::srd::Shear{});
  }
  const std::uint32_t c = granflow::srd::cell_of<3>(x, in.shift, length, grid, granflow::srd::Shear{}, origin, bounded);
  granflow::srd::collide_particle<3>(v, matrices + 9 * c, means + 3 * c, 0.0);
  return c;
}

}  // namespace granflow::cuda::srd
