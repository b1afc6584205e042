#include "cuda/device_query.cuh"

#include <cuda_runtime.h>

#include <stdexcept>
#include <vector>

#include "engine/core/host_device.hpp"

namespace granflow::cuda {

namespace {

GRANFLOW_HD inline double kinetic_energy_of(double mass, double speed_squared) { return 0.5 * mass * speed_squared; }

__global__ void kinetic_energy_kernel(const double* mass, const double* speed_squared, double* energy, int count) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < count) energy[i] = kinetic_energy_of(mass[i], speed_squared[i]);
}

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(status));
}

}  // namespace

DeviceReport query_devices() {
  DeviceReport report;
  const cudaError_t status = cudaGetDeviceCount(&report.count);
  if (status != cudaSuccess) {
    report.count = 0;
    report.message = cudaGetErrorString(status);
    return report;
  }
  report.message = std::to_string(report.count) + " CUDA device(s)";
  return report;
}

double kinetic_energy_on_device(const double* mass, const double* speed_squared, int count) {
  const std::size_t bytes = sizeof(double) * static_cast<std::size_t>(count);
  double *d_mass = nullptr, *d_speed = nullptr, *d_energy = nullptr;
  check(cudaMalloc(&d_mass, bytes), "cudaMalloc");
  check(cudaMalloc(&d_speed, bytes), "cudaMalloc");
  check(cudaMalloc(&d_energy, bytes), "cudaMalloc");
  check(cudaMemcpy(d_mass, mass, bytes, cudaMemcpyHostToDevice), "copy to device");
  check(cudaMemcpy(d_speed, speed_squared, bytes, cudaMemcpyHostToDevice), "copy to device");
  kinetic_energy_kernel<<<(count + 255) / 256, 256>>>(d_mass, d_speed, d_energy, count);
  check(cudaGetLastError(), "kernel launch");
  std::vector<double> energy(static_cast<std::size_t>(count));
  check(cudaMemcpy(energy.data(), d_energy, bytes, cudaMemcpyDeviceToHost), "copy to host");
  cudaFree(d_mass);
  cudaFree(d_speed);
  cudaFree(d_energy);
  double total = 0.0;
  for (double e : energy) total += e;
  return total;
}

}  // namespace granflow::cuda
