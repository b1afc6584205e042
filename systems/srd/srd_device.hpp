#pragma once
// The SRD step with the particle columns resident in a Thrust back end's
// memory: one source (systems/srd/srd_device.cpp) that nvcc compiles for an
// NVIDIA GPU (srd.device = "cuda") and g++ compiles for Thrust's oneTBB host
// back end (srd.device = "thrust_host"), so that the step's orchestration
// runs in every build and is tested on the CPU before any GPU sees it.
// Plain C++ types only: host code includes it without CUDA or Thrust headers.
//
// Each stage calls the same GRANFLOW_HD functions as the CPU systems, in
// the same order: streaming (systems/srd/srd_walls.hpp, srd_kernels.hpp),
// the shifted cell of each particle, a stable sort of (cell, particle), each
// cell's sums in storage order about its first particle and its ghosts
// (srd_cell_kernels.hpp), each cell's collision operator, each particle's
// collision, then the thermostat. Every `reorder_interval` steps the columns
// are gathered into cell order, as the CPU's counting sort puts them, so
// both keep the particles in the same order. Global sums (the thermostat's,
// the energy ledger's, the counts) add fixed blocks of particles and then
// the blocks in order, so they are the same on any thread count and back end.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/profiler.hpp"
#include "systems/srd/srd_cell_kernels.hpp"
#include "systems/srd/srd_kernels.hpp"
#include "systems/srd/srd_walls.hpp"

namespace granflow::device {

// The back end this build compiled the step for: "cuda" or "thrust_host".
const char* srd_device_backend();

// Empty where the back end is usable (the host one always is); otherwise why
// not (no CUDA driver, no device), in words for an error message.
std::string srd_device_unavailable();

struct SrdDeviceSetup {
  int dimension = 3;
  std::int32_t cells[3] = {1, 1, 1};  // of the grid (bounded axes with their outer layers)
  double length[3] = {1, 1, 1};       // of the periodic box
  double origin[3] = {0, 0, 0};
  unsigned bounded = 0;
  srd::Wall walls[6];
  int wall_count = 0;
  srd::BodyForce<3> force;  // its first `dimension` axes
  double dt = 1.0;
  double particle_mass = 1.0;
  double ghost_fill = 0.0;
  std::uint64_t seed = 0;
  srd::CellRotation<3> rotation;  // the angle and rule; each cell draws its own axis
  srd::GranularParameters granular;
  bool shear = false;            // Lees-Edwards planes along y
  bool record_moments = false;   // and the collisional transfer per cell
  bool record_energy = false;    // wall work and collision energy per step
  double thermostat = 0.0;       // target temperature (0: none)
  bool thermostat_removes_drift = true;
  std::uint64_t reorder_interval = 20;
};

// What the host supplies per step: its number, the times it starts and ends
// at, the grid shift and the Lees-Edwards state (computed on the host as the
// CPU systems compute them).
struct SrdDeviceStep {
  std::uint64_t step = 0;
  double start_time = 0.0, end_time = 0.0;
  double shift[3] = {0, 0, 0};
  srd::Shear shear;
};

// Sums over the particles that observers sampling every step need, so that
// the state is not copied back for them: per layer one cell thick across
// `axis` (positions below 0 or beyond the last layer counted in the outer
// ones), 3 + D numbers: particles, sum of v[flow], of |v|^2 and of each v_a;
// with `stress`, the sums of vx vy, vy (y - L_y / 2) and vy^2 over all
// particles, and of the collisional transfer over the cells.
struct SrdLayerRequest {
  int axis = 0;
  int flow = 0;
  int layers = 1;
};
struct SrdSumRequests {
  std::vector<SrdLayerRequest> layers;
  bool stress = false;
};

struct SrdDeviceReport {
  std::uint64_t reflections = 0;
  std::uint64_t stranded = 0;  // particles that needed more than srd::most_reflections
  std::uint64_t clamped_cells = 0;
  double wall_work = 0.0;
  double collision_energy = 0.0;
  double ghost_cell_energy = 0.0;
  std::vector<std::vector<double>> layer_sums;  // per request, layers x (3 + D)
  double stress_sums[3] = {0, 0, 0};            // vx vy, vy (y - L_y / 2), vy^2
  double transfer_sum = 0.0;
};

// Host arrays download() fills: particles (D doubles each for x and v), per
// particle its cell and (with shear) its Lees-Edwards image, per cell its
// count, ghosts, mass, mean velocity (D doubles), theta and (with moments)
// the collisional transfer. A null pointer skips that array.
struct SrdHostArrays {
  double* x = nullptr;
  double* v = nullptr;
  std::uint32_t* cell = nullptr;
  std::int8_t* image = nullptr;
  std::uint32_t* count = nullptr;
  std::uint32_t* ghosts = nullptr;
  double* mass = nullptr;
  double* velocity = nullptr;
  double* theta = nullptr;
  double* transfer = nullptr;
};

class SrdDevice {
 public:
  // Throws std::runtime_error naming the problem where no device is usable
  // or its memory is too small.
  SrdDevice(const SrdDeviceSetup& setup, std::size_t particles);
  ~SrdDevice();
  SrdDevice(const SrdDevice&) = delete;
  SrdDevice& operator=(const SrdDevice&) = delete;

  void upload(const double* x, const double* v);
  // One step, and the sums `sums` asks for at its end.
  SrdDeviceReport step(const SrdDeviceStep& step, const SrdSumRequests& sums = {});
  void download(const SrdHostArrays& host);
  // Per stage: calls and time (between CUDA events on a GPU, by the wall
  // clock on the host).
  std::vector<ProfileEntry> profile() const;
  // Memory the back end holds, in bytes.
  std::size_t bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granflow::device
