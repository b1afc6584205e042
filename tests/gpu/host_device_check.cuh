#pragma once
// Kernels that evaluate the shared GRANFLOW_HD physics on the device, one
// item per thread, for comparison with the same functions on the host
// (tests/gpu/host_device_test.cpp). Plain-pointer drivers: host arrays in,
// host arrays out; each throws std::runtime_error naming the CUDA error.

#include <cstdint>

namespace granflow::cuda {

// words[4 * i + k] = Philox(stream, seed, step, i).next_words()[k], i < count.
void philox_words_on_device(std::uint32_t stream, std::uint64_t seed, std::uint64_t step, int count,
                            std::uint32_t* words);

// One exact-OU (scheme 0) or Euler-Maruyama (scheme 1) step of one component
// per particle, with the noise drawn as the SDE kernel draws it.
struct SdeCheckInput {
  double gamma0, diffusivity0, tau0, time, dt;
  std::uint64_t seed, step;
  int scheme;
};
void sde_step_on_device(const SdeCheckInput& input, int count, double* x, double* v);

// Pair collisions in 3D: v holds (vi, vj) as 6 doubles per pair, dx 3 per
// pair, mass 2 per pair; dissipated gets one value per pair.
void pair_collisions_on_device(int count, double restitution, const double* mass, const double* dx, double* v,
                               double* dissipated);

// The SRD functions of one step in 3D (systems/srd/srd_kernels.hpp,
// srd_walls.hpp). Cells: each one's collision matrix from its random axis
// (rotation by alpha, every cell scaled by `eps`, as granular SRD does).
// Particles: streaming in the periodic box of `cells`, or, with `walls`,
// between no-slip walls at z = 0 and z = cells[2] under the acceleration
// `gravity` along z; then the particle's cell in the grid shifted by
// `shift` (with walls: one layer beyond each wall, origin -1); then its
// collision with that cell's matrix and mean velocity (9 and 3 doubles per
// cell of that grid).
struct SrdCheckInput {
  int cells[3];
  double shift[3];
  double dt, cos_alpha, sin_alpha, eps, gravity;
  std::uint64_t seed, step;
  int walls;
};
void srd_cell_matrices_on_device(const SrdCheckInput& input, int cell_count, double* matrices);
void srd_particles_on_device(const SrdCheckInput& input, int count, const double* matrices, const double* means,
                             double* x, double* v, std::uint32_t* cell);

}  // namespace granflow::cuda
