#include "tests/gpu/host_device_check.cuh"

#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "systems/edmd/collision_rule.hpp"
#include "systems/sde/gaussian_noise.hpp"
#include "systems/sde/sde_model.hpp"
#include "tests/gpu/srd_check_step.cuh"

namespace granflow::cuda {

namespace {

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(status));
}

// Device copies of host arrays, freed on scope exit.
template <class T>
class DeviceArray {
 public:
  DeviceArray(const T* host, std::size_t count) : count_(count) {
    check(cudaMalloc(&data_, sizeof(T) * count), "cudaMalloc");
    if (host) check(cudaMemcpy(data_, host, sizeof(T) * count, cudaMemcpyHostToDevice), "copy to device");
  }
  ~DeviceArray() { cudaFree(data_); }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
  T* get() { return data_; }
  void copy_to(T* host) const {
    check(cudaMemcpy(host, data_, sizeof(T) * count_, cudaMemcpyDeviceToHost), "copy to host");
  }

 private:
  T* data_ = nullptr;
  std::size_t count_;
};

constexpr int threads = 128;
int blocks_for(int count) { return (count + threads - 1) / threads; }

__global__ void philox_kernel(std::uint32_t stream, std::uint64_t seed, std::uint64_t step, int count,
                              std::uint32_t* words) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  Philox random(stream, seed, step, static_cast<std::uint64_t>(i));
  const auto w = random.next_words();
  for (int k = 0; k < 4; ++k) words[4 * i + k] = w[k];
}

__global__ void sde_kernel(SdeCheckInput in, int count, double* x, double* v) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  std::uint32_t c0 = static_cast<std::uint32_t>(i), c1 = 0, c2 = static_cast<std::uint32_t>(in.step),
                c3 = stream::sde_noise << 16;
  sde::philox4x32_10(c0, c1, c2, c3, static_cast<std::uint32_t>(in.seed), static_cast<std::uint32_t>(in.seed >> 32));
  const float noise = sde::box_muller_radius(c0) * cosf(sde::box_muller_angle(c1));
  sde::SdeModel model;
  model.gamma0 = in.gamma0;
  model.diffusivity0 = in.diffusivity0;
  model.tau0 = in.tau0;
  if (in.scheme == 1)
    sde::euler_maruyama_step(x[i], v[i], model.friction(in.time), model.diffusivity(in.time), in.dt, noise);
  else
    sde::drift_ou_drift_step(x[i], v[i], sde::exact_velocity_update(model, in.time, in.dt), in.dt, noise);
}

__global__ void collision_kernel(int count, double restitution, const double* mass, const double* dx, double* v,
                                 double* dissipated) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  Vec<3> vi(v[6 * i], v[6 * i + 1], v[6 * i + 2]), vj(v[6 * i + 3], v[6 * i + 4], v[6 * i + 5]);
  const Vec<3> separation(dx[3 * i], dx[3 * i + 1], dx[3 * i + 2]);
  const auto result = edmd::collide_pair<3>(vi, vj, mass[2 * i], mass[2 * i + 1], separation, restitution);
  for (int a = 0; a < 3; ++a) {
    v[6 * i + a] = vi[a];
    v[6 * i + 3 + a] = vj[a];
  }
  dissipated[i] = result.dissipated_energy;
}

__global__ void srd_cell_kernel(SrdCheckInput in, int count, double* matrices) {
  const int c = blockIdx.x * blockDim.x + threadIdx.x;
  if (c >= count) return;
  srd::check_cell_matrix(in, static_cast<std::uint64_t>(c), matrices + 9 * c);
}

__global__ void srd_particle_kernel(SrdCheckInput in, int count, const double* matrices, const double* means,
                                    double* x, double* v, std::uint32_t* cell) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  cell[i] = srd::check_particle_step(in, matrices, means, x + 3 * i, v + 3 * i);
}

}  // namespace

void srd_cell_matrices_on_device(const SrdCheckInput& input, int cell_count, double* matrices) {
  DeviceArray<double> out(nullptr, 9 * static_cast<std::size_t>(cell_count));
  srd_cell_kernel<<<blocks_for(cell_count), threads>>>(input, cell_count, out.get());
  check(cudaGetLastError(), "SRD cell kernel");
  out.copy_to(matrices);
}

void srd_particles_on_device(const SrdCheckInput& input, int count, const double* matrices, const double* means,
                             double* x, double* v, std::uint32_t* cell) {
  int cell_count = input.cells[0] * input.cells[1] * (input.cells[2] + (input.walls ? 2 : 0));
  const auto n = static_cast<std::size_t>(count), cells = static_cast<std::size_t>(cell_count);
  DeviceArray<double> d_m(matrices, 9 * cells), d_mean(means, 3 * cells), d_x(x, 3 * n), d_v(v, 3 * n);
  DeviceArray<std::uint32_t> d_cell(nullptr, n);
  srd_particle_kernel<<<blocks_for(count), threads>>>(input, count, d_m.get(), d_mean.get(), d_x.get(), d_v.get(),
                                                      d_cell.get());
  check(cudaGetLastError(), "SRD particle kernel");
  d_x.copy_to(x);
  d_v.copy_to(v);
  d_cell.copy_to(cell);
}

void philox_words_on_device(std::uint32_t stream, std::uint64_t seed, std::uint64_t step, int count,
                            std::uint32_t* words) {
  DeviceArray<std::uint32_t> out(nullptr, 4 * static_cast<std::size_t>(count));
  philox_kernel<<<blocks_for(count), threads>>>(stream, seed, step, count, out.get());
  check(cudaGetLastError(), "philox kernel");
  out.copy_to(words);
}

void sde_step_on_device(const SdeCheckInput& input, int count, double* x, double* v) {
  DeviceArray<double> dx(x, count), dv(v, count);
  sde_kernel<<<blocks_for(count), threads>>>(input, count, dx.get(), dv.get());
  check(cudaGetLastError(), "SDE kernel");
  dx.copy_to(x);
  dv.copy_to(v);
}

void pair_collisions_on_device(int count, double restitution, const double* mass, const double* dx, double* v,
                               double* dissipated) {
  const auto n = static_cast<std::size_t>(count);
  DeviceArray<double> d_mass(mass, 2 * n), d_dx(dx, 3 * n), d_v(v, 6 * n), d_lost(nullptr, n);
  collision_kernel<<<blocks_for(count), threads>>>(count, restitution, d_mass.get(), d_dx.get(), d_v.get(),
                                                   d_lost.get());
  check(cudaGetLastError(), "collision kernel");
  d_v.copy_to(v);
  d_lost.copy_to(dissipated);
}

}  // namespace granflow::cuda
