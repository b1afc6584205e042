#include "cuda/srd_device.cuh"

#include <cuda_runtime.h>

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_reduce.cuh>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "engine/rng.hpp"

namespace granflow::cuda {

namespace {

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) throw std::runtime_error(std::string("CUDA: ") + what + ": " + cudaGetErrorString(status));
}

template <class T>
class Buffer {
 public:
  Buffer() = default;
  explicit Buffer(std::size_t count) { resize(count); }
  ~Buffer() { cudaFree(data_); }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  void resize(std::size_t count) {
    if (count == count_) return;
    cudaFree(data_);
    data_ = nullptr;
    count_ = count;
    if (count > 0) check(cudaMalloc(&data_, sizeof(T) * count), "cudaMalloc (device memory too small?)");
  }
  void swap(Buffer& other) {
    std::swap(data_, other.data_);
    std::swap(count_, other.count_);
  }
  T* get() const { return data_; }
  std::size_t bytes() const { return sizeof(T) * count_; }
  std::size_t size() const { return count_; }

 private:
  T* data_ = nullptr;
  std::size_t count_ = 0;
};

constexpr int threads = 256;
unsigned blocks_for(std::size_t count) { return static_cast<unsigned>((count + threads - 1) / threads); }

// The layer of this step's grid a no-slip wall with ghosts cuts.
struct CutLayer {
  int wall;
  std::uint32_t stride;
  std::int64_t layer;
};

struct StepConstants {
  SrdDeviceSetup setup;
  SrdDeviceStep step;
  CutLayer cuts[6];
  int cut_count;
};

template <int D>
__global__ void stream_kernel(StepConstants k, std::size_t n, double* x, double* v, std::uint32_t* cell,
                              std::int8_t* image, double* work, unsigned long long* reflections) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const SrdDeviceSetup& s = k.setup;
  double* xi = x + D * i;
  double* vi = v + D * i;
  srd::BodyForce<D> force;
  for (int a = 0; a < D; ++a) force.acceleration[a] = s.acceleration[a];
  force.slab_axis = s.slab_axis;
  force.from = s.slab_from;
  force.to = s.slab_to;
  if (s.wall_count == 0 && !force.any()) {
    srd::stream_particle<D>(xi, vi, s.dt, s.length, k.step.shear);
  } else {
    const double none[D] = {};
    const double* g = force.acts_at(xi) ? force.acceleration : none;
    double gained = 0.0;
    const int hits = srd::stream_between_walls<D>(xi, vi, g, k.step.start_time, s.dt, s.walls, s.wall_count,
                                                  work ? &gained : nullptr);
    for (int a = 0; a < D; ++a)
      if (!(s.bounded & (1u << a))) xi[a] = srd::wrapped(xi[a], s.length[a]);
    if (work) work[i] = gained;
    if (hits) atomicAdd(reflections, static_cast<unsigned long long>(hits));
  }
  std::int32_t grid[D];
  for (int a = 0; a < D; ++a) grid[a] = s.cells[a];
  cell[i] = srd::cell_of<D>(xi, k.step.shift, s.length, grid, k.step.shear, s.origin, s.bounded);
  if (image) image[i] = static_cast<std::int8_t>(srd::shear_image<D>(xi, k.step.shift, s.length));
}

__global__ void iota_kernel(std::size_t n, std::uint32_t* out) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n) out[i] = static_cast<std::uint32_t>(i);
}

// start[c], end[c] of each occupied cell in the sorted keys (others stay 0).
__global__ void bounds_kernel(std::size_t n, const std::uint32_t* sorted, std::uint32_t* start, std::uint32_t* end) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k >= n) return;
  const std::uint32_t c = sorted[k];
  if (k == 0 || sorted[k - 1] != c) start[c] = static_cast<std::uint32_t>(k);
  if (k + 1 == n || sorted[k + 1] != c) end[c] = static_cast<std::uint32_t>(k + 1);
}

template <int D>
__global__ void reduce_kernel(StepConstants k, std::size_t cell_count, const std::uint32_t* order,
                              const std::uint32_t* start, const std::uint32_t* end, const double* x, const double* v,
                              const std::int8_t* image, std::uint32_t* count, std::uint32_t* ghosts, double* mass,
                              double* velocity, double* theta, double* moment) {
  const std::size_t c = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (c >= cell_count) return;
  const SrdDeviceSetup& s = k.setup;
  const std::uint32_t first = start[c], last = end[c];
  const std::uint32_t members = last - first;
  count[c] = members;
  if (ghosts) ghosts[c] = 0;
  if (members == 0) {
    mass[c] = 0.0;
    theta[c] = 0.0;
    for (int a = 0; a < D; ++a) velocity[D * c + a] = 0.0;
    return;
  }
  srd::CellSums<D> sums;
  double m_moment[D] = {}, moment_mass = 0.0;
  const double y_shift = D >= 2 ? k.step.shift[1] : 0.0;
  for (std::uint32_t q = first; q < last; ++q) {
    const std::uint32_t i = order[q];
    double seen[D];
    for (int a = 0; a < D; ++a) seen[a] = v[D * i + a];
    if (image) seen[0] -= image[i] * k.step.shear.velocity;
    if (q == first) srd::start_sums<D>(sums, seen);
    double w[D];
    srd::add_to_sums<D>(sums, seen, s.particle_mass, w);
    if (moment) {
      const double y = x[D * i + 1] + y_shift;
      const double offset = s.particle_mass * (y - static_cast<double>(srd::floor_index(y)) - 0.5);
      for (int a = 0; a < D; ++a) m_moment[a] += offset * w[a];
      moment_mass += offset;
    }
  }
  std::uint32_t added = 0;
  for (int q = 0; q < k.cut_count; ++q) {
    const CutLayer& cut = k.cuts[q];
    const srd::Wall& wall = s.walls[cut.wall];
    const auto along = static_cast<std::uint32_t>(s.cells[wall.axis]);
    if (static_cast<std::int64_t>((c / cut.stride) % along) != cut.layer) continue;
    const int missing = srd::ghost_count(members, s.ghost_fill);
    if (missing > 0) {
      srd::add_ghosts_to_sums<D>(sums, missing, wall, k.step.end_time, s.particle_mass, s.seed, k.step.step, c);
      added = static_cast<std::uint32_t>(missing);
    }
    break;
  }
  if (ghosts) ghosts[c] = added;
  double drift[D], mean[D], t;
  srd::finish_sums<D>(sums, static_cast<double>(members + added), mean, t, drift);
  for (int a = 0; a < D; ++a) velocity[D * c + a] = mean[a];
  theta[c] = t;
  mass[c] = sums.mass;
  if (moment)
    for (int a = 0; a < D; ++a) moment[D * c + a] = m_moment[a] - moment_mass * drift[a];
}

template <int D>
__global__ void matrix_kernel(StepConstants k, std::size_t cell_count, const std::uint32_t* count,
                              const std::uint32_t* ghosts, const double* theta, const double* moment, double* matrices,
                              double* transfer, unsigned long long* clamped) {
  const std::size_t c = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (c >= cell_count) return;
  const SrdDeviceSetup& s = k.setup;
  srd::CellRotation<D> base;
  base.cos_alpha = s.cos_alpha;
  base.sin_alpha = s.sin_alpha;
  base.rule = s.rule;
  const double members = count[c] + (ghosts ? ghosts[c] : 0u);
  bool below_zero = false;
  double* matrix = matrices + D * D * c;
  srd::cell_collision_matrix<D>(base, s.granular, s.seed, k.step.step, c, members, theta[c], matrix, below_zero);
  if (below_zero) atomicAdd(clamped, 1ull);
  if (transfer) transfer[c] = members >= 2 ? srd::collisional_transfer<D>(matrix, moment + D * c) : 0.0;
}

template <int D>
__global__ void collide_kernel(StepConstants k, std::size_t n, double* v, const std::uint32_t* cell,
                               const std::int8_t* image, const double* matrices, const double* velocity,
                               const std::uint32_t* ghosts, double* plain, double* ghosted) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  double* vi = v + D * i;
  const std::uint32_t c = cell[i];
  double before = 0.0, after = 0.0;
  if (plain)
    for (int a = 0; a < D; ++a) before += vi[a] * vi[a];
  srd::collide_particle<D>(vi, matrices + D * D * c, velocity + D * c, image ? -image[i] * k.step.shear.velocity : 0.0);
  if (!plain) return;
  for (int a = 0; a < D; ++a) after += vi[a] * vi[a];
  const double change = 0.5 * (after - before);
  const bool with_ghosts = ghosts && ghosts[c] > 0;
  plain[i] = with_ghosts ? 0.0 : change;
  ghosted[i] = with_ghosts ? change : 0.0;
}

// Per particle: m v_a (a < D), and m |v - V_cell|^2 as the cell sees it.
template <int D>
__global__ void thermostat_terms_kernel(StepConstants k, std::size_t n, const double* v, const std::uint32_t* cell,
                                        const std::int8_t* image, const double* velocity, double* terms) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const double m = k.setup.particle_mass;
  double u2 = 0.0;
  for (int a = 0; a < D; ++a) {
    double u = v[D * i + a] - velocity[D * cell[i] + a];
    if (a == 0 && image) u -= image[i] * k.step.shear.velocity;
    u2 += u * u;
    terms[a * n + i] = m * v[D * i + a];
  }
  terms[D * n + i] = m * u2;
}

__global__ void occupied_kernel(std::size_t cell_count, const std::uint32_t* count, double* out) {
  const std::size_t c = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (c < cell_count) out[c] = count[c] > 0 ? 1.0 : 0.0;
}

template <int D>
__global__ void thermostat_kernel(StepConstants k, std::size_t n, double* v, const std::uint32_t* cell,
                                  const std::int8_t* image, const double* velocity, double factor, double d0,
                                  double d1, double d2) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const double drift[3] = {d0, d1, d2};
  const double image_velocity = image ? -image[i] * k.step.shear.velocity : 0.0;
  for (int a = 0; a < D; ++a) {
    const double mean = velocity[D * cell[i] + a];
    double u = v[D * i + a] - mean;
    if (a == 0) u += image_velocity;
    v[D * i + a] = mean - drift[a] + factor * u - (a == 0 ? image_velocity : 0.0);
  }
}

template <int D>
__global__ void shift_means_kernel(std::size_t cell_count, double* velocity, double d0, double d1, double d2) {
  const std::size_t c = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (c >= cell_count) return;
  const double drift[3] = {d0, d1, d2};
  for (int a = 0; a < D; ++a) velocity[D * c + a] -= drift[a];
}

// Gathers D doubles per particle into cell order.
template <int D>
__global__ void gather_kernel(std::size_t n, const std::uint32_t* order, const double* from, double* to) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k >= n) return;
  const std::uint32_t i = order[k];
  for (int a = 0; a < D; ++a) to[D * k + a] = from[D * i + a];
}

__global__ void gather_image_kernel(std::size_t n, const std::uint32_t* order, const std::int8_t* from, std::int8_t* to) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < n) to[k] = from[order[k]];
}

// The stages /profile names, timed by events around them.
enum Stage { stream_stage, sort_stage, reduce_stage, collide_stage, thermostat_stage, reorder_stage, stage_count };
constexpr const char* stage_names[stage_count] = {"srd_device_step/stream_and_bin", "srd_device_step/sort",
                                                  "srd_device_step/reduce", "srd_device_step/collide",
                                                  "srd_device_step/thermostat", "srd_device_step/reorder"};

}  // namespace

std::string srd_device_unavailable() {
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess) return std::string("no usable CUDA driver or device (") + cudaGetErrorString(status) + ")";
  if (count == 0) return "no CUDA device found";
  return {};
}

struct SrdDevice::Impl {
  SrdDeviceSetup setup;
  std::size_t n = 0, cell_count = 0;
  Buffer<double> x, v, x_spare, v_spare;
  Buffer<std::uint32_t> cell, sorted_cell, iota, order, start, end;
  Buffer<std::int8_t> image, image_spare;
  Buffer<std::uint32_t> count, ghosts;
  Buffer<double> mass, velocity, theta, matrices, moment, transfer;
  Buffer<double> work, plain, ghosted, terms, occupied, sums;
  Buffer<unsigned long long> counters;  // reflections, clamped cells of this step
  Buffer<unsigned char> scratch;        // CUB's
  int sort_bits = 32;
  cudaEvent_t events[2 * stage_count] = {};
  bool timed[stage_count] = {};
  ProfileEntry entries[stage_count];
  std::uint64_t steps_done = 0;

  void begin(Stage s) {
    check(cudaEventRecord(events[2 * s]), "cudaEventRecord");
    timed[s] = true;
  }
  void finish(Stage s) { check(cudaEventRecord(events[2 * s + 1]), "cudaEventRecord"); }
  void collect_times() {
    for (int s = 0; s < stage_count; ++s) {
      if (!timed[s]) continue;
      float ms = 0.0f;
      check(cudaEventElapsedTime(&ms, events[2 * s], events[2 * s + 1]), "cudaEventElapsedTime");
      entries[s].calls += 1;
      entries[s].total_seconds += 1e-3 * ms;
      timed[s] = false;
    }
  }

  // Sum of `count` doubles on the device (CUB), into sums[slot].
  void sum_into(const double* in, std::size_t count_in, int slot) {
    std::size_t bytes = 0;
    check(cub::DeviceReduce::Sum(nullptr, bytes, in, sums.get() + slot, count_in), "cub::DeviceReduce::Sum");
    if (bytes > scratch.size()) scratch.resize(bytes);
    check(cub::DeviceReduce::Sum(scratch.get(), bytes, in, sums.get() + slot, count_in), "cub::DeviceReduce::Sum");
  }

  template <int D>
  SrdDeviceReport step(const SrdDeviceStep& in);
};

SrdDevice::SrdDevice(const SrdDeviceSetup& setup, std::size_t particles) : impl_(std::make_unique<Impl>()) {
  const std::string unavailable = srd_device_unavailable();
  if (!unavailable.empty()) throw std::runtime_error(unavailable);
  Impl& d = *impl_;
  d.setup = setup;
  d.n = particles;
  d.cell_count = 1;
  for (int a = 0; a < setup.dimension; ++a) d.cell_count *= static_cast<std::size_t>(setup.cells[a]);
  const std::size_t n = particles, dim = static_cast<std::size_t>(setup.dimension), cells = d.cell_count;
  d.x.resize(dim * n);
  d.v.resize(dim * n);
  d.x_spare.resize(dim * n);
  d.v_spare.resize(dim * n);
  d.cell.resize(n);
  d.sorted_cell.resize(n);
  d.iota.resize(n);
  d.order.resize(n);
  d.start.resize(cells);
  d.end.resize(cells);
  d.count.resize(cells);
  if (setup.wall_count > 0) d.ghosts.resize(cells);
  d.mass.resize(cells);
  d.velocity.resize(dim * cells);
  d.theta.resize(cells);
  d.matrices.resize(dim * dim * cells);
  if (setup.shear) {
    d.image.resize(n);
    d.image_spare.resize(n);
  }
  if (setup.record_moments) {
    d.moment.resize(dim * cells);
    d.transfer.resize(cells);
  }
  if (setup.record_energy) {
    d.work.resize(n);
    d.plain.resize(n);
    d.ghosted.resize(n);
  }
  if (setup.thermostat > 0.0) {
    d.terms.resize((dim + 1) * n);
    d.occupied.resize(cells);
  }
  d.sums.resize(8);
  d.counters.resize(2);
  // Only the bits a cell index can have are sorted.
  d.sort_bits = 1;
  while (d.sort_bits < 32 && (std::uint64_t{1} << d.sort_bits) < cells) ++d.sort_bits;
  std::size_t bytes = 0;
  check(cub::DeviceRadixSort::SortPairs(nullptr, bytes, d.cell.get(), d.sorted_cell.get(), d.iota.get(), d.order.get(),
                                        n, 0, d.sort_bits),
        "cub::DeviceRadixSort::SortPairs");
  d.scratch.resize(bytes);
  iota_kernel<<<blocks_for(n), threads>>>(n, d.iota.get());
  check(cudaGetLastError(), "iota kernel");
  for (auto& e : d.events) check(cudaEventCreate(&e), "cudaEventCreate");
  for (int s = 0; s < stage_count; ++s) d.entries[s].system = stage_names[s];
}

SrdDevice::~SrdDevice() {
  for (auto& e : impl_->events)
    if (e) cudaEventDestroy(e);
}

void SrdDevice::upload(const double* x, const double* v) {
  Impl& d = *impl_;
  check(cudaMemcpy(d.x.get(), x, d.x.bytes(), cudaMemcpyHostToDevice), "copy of positions to the device");
  check(cudaMemcpy(d.v.get(), v, d.v.bytes(), cudaMemcpyHostToDevice), "copy of velocities to the device");
}

template <int D>
SrdDeviceReport SrdDevice::Impl::step(const SrdDeviceStep& in) {
  StepConstants k{};
  k.setup = setup;
  k.step = in;
  // The layers the no-slip walls with ghosts cut at the step's end, as the CPU reduction finds them.
  const double time = in.end_time;
  for (int w = 0; w < setup.wall_count; ++w) {
    const srd::Wall& wall = setup.walls[w];
    if (wall.kind != srd::WallKind::no_slip || !wall.ghosts) continue;
    std::uint32_t stride = 1;
    for (int b = 0; b < wall.axis; ++b) stride *= static_cast<std::uint32_t>(setup.cells[b]);
    k.cuts[k.cut_count++] = {w, stride, srd::floor_index(wall.position(time) + in.shift[wall.axis] - setup.origin[wall.axis])};
  }
  check(cudaMemset(counters.get(), 0, counters.bytes()), "cudaMemset");
  const unsigned pb = blocks_for(n), cb = blocks_for(cell_count);
  std::int8_t* img = setup.shear ? image.get() : nullptr;

  begin(stream_stage);
  stream_kernel<D><<<pb, threads>>>(k, n, x.get(), v.get(), cell.get(), img, setup.record_energy ? work.get() : nullptr,
                                    counters.get());
  check(cudaGetLastError(), "streaming kernel");
  finish(stream_stage);

  begin(sort_stage);
  std::size_t bytes = scratch.size();
  check(cub::DeviceRadixSort::SortPairs(scratch.get(), bytes, cell.get(), sorted_cell.get(), iota.get(), order.get(), n,
                                        0, sort_bits),
        "cub::DeviceRadixSort::SortPairs");
  check(cudaMemset(start.get(), 0, start.bytes()), "cudaMemset");
  check(cudaMemset(end.get(), 0, end.bytes()), "cudaMemset");
  bounds_kernel<<<pb, threads>>>(n, sorted_cell.get(), start.get(), end.get());
  check(cudaGetLastError(), "cell bounds kernel");
  finish(sort_stage);

  // At reorderings the columns are gathered into cell order (stable: the
  // order the CPU's counting sort gives), and the order becomes the identity.
  const std::uint32_t* order_now = order.get();
  if (setup.reorder_interval > 0 && in.step % setup.reorder_interval == 0) {
    begin(reorder_stage);
    gather_kernel<D><<<pb, threads>>>(n, order.get(), x.get(), x_spare.get());
    gather_kernel<D><<<pb, threads>>>(n, order.get(), v.get(), v_spare.get());
    if (img) gather_image_kernel<<<pb, threads>>>(n, order.get(), image.get(), image_spare.get());
    check(cudaGetLastError(), "gather kernels");
    x.swap(x_spare);
    v.swap(v_spare);
    if (img) {
      image.swap(image_spare);
      img = image.get();
    }
    check(cudaMemcpy(cell.get(), sorted_cell.get(), cell.bytes(), cudaMemcpyDeviceToDevice), "copy of sorted cells");
    order_now = iota.get();
    finish(reorder_stage);
  }

  begin(reduce_stage);
  reduce_kernel<D><<<cb, threads>>>(k, cell_count, order_now, start.get(), end.get(), x.get(), v.get(), img, count.get(),
                                    setup.wall_count > 0 ? ghosts.get() : nullptr, mass.get(), velocity.get(), theta.get(),
                                    setup.record_moments ? moment.get() : nullptr);
  check(cudaGetLastError(), "cell reduction kernel");
  finish(reduce_stage);

  begin(collide_stage);
  matrix_kernel<D><<<cb, threads>>>(k, cell_count, count.get(), setup.wall_count > 0 ? ghosts.get() : nullptr, theta.get(),
                                    setup.record_moments ? moment.get() : nullptr, matrices.get(),
                                    setup.record_moments ? transfer.get() : nullptr, counters.get() + 1);
  collide_kernel<D><<<pb, threads>>>(k, n, v.get(), cell.get(), img, matrices.get(), velocity.get(),
                                     setup.wall_count > 0 ? ghosts.get() : nullptr,
                                     setup.record_energy ? plain.get() : nullptr,
                                     setup.record_energy ? ghosted.get() : nullptr);
  check(cudaGetLastError(), "collision kernels");
  if (setup.record_energy) {
    sum_into(work.get(), n, 0);
    sum_into(plain.get(), n, 1);
    sum_into(ghosted.get(), n, 2);
  }
  finish(collide_stage);

  SrdDeviceReport report;
  if (setup.thermostat > 0.0) {
    begin(thermostat_stage);
    thermostat_terms_kernel<D><<<pb, threads>>>(k, n, v.get(), cell.get(), img, velocity.get(), terms.get());
    occupied_kernel<<<cb, threads>>>(cell_count, count.get(), occupied.get());
    check(cudaGetLastError(), "thermostat sums");
    for (int a = 0; a <= D; ++a) sum_into(terms.get() + static_cast<std::size_t>(a) * n, n, 3 + a);
    sum_into(occupied.get(), cell_count, 7);
    double s[8];
    check(cudaMemcpy(s, sums.get(), sizeof s, cudaMemcpyDeviceToHost), "copy of the thermostat's sums");
    double drift[3] = {0, 0, 0};
    if (setup.thermostat_removes_drift)
      for (int a = 0; a < D; ++a) drift[a] = s[3 + a] / (setup.particle_mass * static_cast<double>(n));
    const double thermal = s[3 + D], dof = D * (static_cast<double>(n) - s[7]);
    if (thermal > 0.0 && dof > 0.0) {
      const double factor = std::sqrt(setup.thermostat * dof / thermal);
      thermostat_kernel<D><<<pb, threads>>>(k, n, v.get(), cell.get(), img, velocity.get(), factor, drift[0], drift[1],
                                            drift[2]);
      shift_means_kernel<D><<<cb, threads>>>(cell_count, velocity.get(), drift[0], drift[1], drift[2]);
      check(cudaGetLastError(), "thermostat kernels");
    }
    finish(thermostat_stage);
  }

  unsigned long long counts[2];
  check(cudaMemcpy(counts, counters.get(), sizeof counts, cudaMemcpyDeviceToHost), "copy of the step's counts");
  report.reflections = counts[0];
  report.clamped_cells = counts[1];
  if (setup.record_energy) {
    double s[3];
    check(cudaMemcpy(s, sums.get(), sizeof s, cudaMemcpyDeviceToHost), "copy of the step's energies");
    report.wall_work = setup.particle_mass * s[0];
    report.collision_energy = setup.particle_mass * s[1];
    report.ghost_cell_energy = setup.particle_mass * s[2];
  }
  check(cudaDeviceSynchronize(), "SRD step");
  collect_times();
  ++steps_done;
  return report;
}

SrdDeviceReport SrdDevice::step(const SrdDeviceStep& step) {
  return impl_->setup.dimension == 2 ? impl_->step<2>(step) : impl_->step<3>(step);
}

void SrdDevice::download(const SrdHostArrays& host) {
  Impl& d = *impl_;
  const auto copy = [](void* to, const void* from, std::size_t bytes, const char* what) {
    if (to && bytes > 0) check(cudaMemcpy(to, from, bytes, cudaMemcpyDeviceToHost), what);
  };
  copy(host.x, d.x.get(), d.x.bytes(), "copy of positions to the host");
  copy(host.v, d.v.get(), d.v.bytes(), "copy of velocities to the host");
  copy(host.cell, d.cell.get(), d.cell.bytes(), "copy of cells to the host");
  copy(host.image, d.image.get(), d.image.bytes(), "copy of images to the host");
  copy(host.count, d.count.get(), d.count.bytes(), "copy of cell counts to the host");
  copy(host.ghosts, d.ghosts.get(), d.ghosts.bytes(), "copy of ghost counts to the host");
  copy(host.mass, d.mass.get(), d.mass.bytes(), "copy of cell masses to the host");
  copy(host.velocity, d.velocity.get(), d.velocity.bytes(), "copy of cell velocities to the host");
  copy(host.theta, d.theta.get(), d.theta.bytes(), "copy of cell temperatures to the host");
  copy(host.transfer, d.transfer.get(), d.transfer.bytes(), "copy of collisional transfers to the host");
}

std::vector<ProfileEntry> SrdDevice::profile() const {
  std::vector<ProfileEntry> out;
  for (const ProfileEntry& e : impl_->entries)
    if (e.calls > 0) out.push_back(e);
  return out;
}

std::size_t SrdDevice::bytes() const {
  const Impl& d = *impl_;
  std::size_t total = d.scratch.bytes();
  for (const auto* b : {&d.x, &d.v, &d.x_spare, &d.v_spare, &d.mass, &d.velocity, &d.theta, &d.matrices, &d.moment,
                        &d.transfer, &d.work, &d.plain, &d.ghosted, &d.terms, &d.occupied, &d.sums})
    total += b->bytes();
  for (const auto* b : {&d.cell, &d.sorted_cell, &d.iota, &d.order, &d.start, &d.end, &d.count, &d.ghosts})
    total += b->bytes();
  return total + d.image.bytes() + d.image_spare.bytes();
}

}  // namespace granflow::cuda
