// The SRD step over Thrust's algorithms (systems/srd/srd_device.hpp): compiled by
// nvcc as CUDA in builds with GRANFLOW_CUDA, by g++ with Thrust's oneTBB
// back end (THRUST_DEVICE_SYSTEM_TBB) otherwise. Each stage is a functor
// applied by thrust::for_each over particle or cell indices, the sort is
// thrust::stable_sort_by_key; no hand-written kernels.

#include "systems/srd/srd_device.hpp"

#include <thrust/copy.h>
#include <thrust/device_vector.h>
#include <thrust/execution_policy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/sequence.h>
#include <thrust/sort.h>

#if defined(__CUDACC__)
#include <cuda_runtime.h>
#endif

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "engine/core/host_device.hpp"
#include "engine/core/rng.hpp"

namespace granflow::device {

namespace {

#if defined(__CUDACC__)
void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) throw std::runtime_error(std::string("CUDA: ") + what + ": " + cudaGetErrorString(status));
}
#endif

template <class T>
using Column = thrust::device_vector<T>;

template <class T>
T* raw(Column<T>& column) {
  return column.empty() ? nullptr : thrust::raw_pointer_cast(column.data());
}
template <class T>
const T* raw(const Column<T>& column) {
  return column.empty() ? nullptr : thrust::raw_pointer_cast(column.data());
}

template <class T>
void copy_to_host(T* to, const Column<T>& from, const char* what) {
  if (!to || from.empty()) return;
  try {
    thrust::copy(from.begin(), from.end(), to);
  } catch (const std::exception& error) {
    throw std::runtime_error(std::string(what) + ": " + error.what());
  }
}

template <class F>
void for_each_index(std::size_t count, const F& f) {
  const thrust::counting_iterator<std::size_t> first(0);
  thrust::for_each(thrust::device, first, first + count, f);
}

struct StepConstants {
  SrdDeviceSetup setup;
  SrdDeviceStep step;
  srd::CutLayer cuts[6];
  int cut_count;
};

template <int D>
struct Stream {
  StepConstants k;
  double* x;
  double* v;
  std::uint32_t* cell;
  std::int8_t* image;
  double* work;
  std::uint8_t* hits;  // per particle, its wall reflections (with walls only), summed afterwards
  GRANFLOW_HD void operator()(std::size_t i) const {
    const SrdDeviceSetup& s = k.setup;
    double* xi = x + D * i;
    double* vi = v + D * i;
    const srd::BodyForce<3>& force = s.force;  // its first D axes
    if (s.wall_count == 0 && !force.any()) {
      srd::stream_particle<D>(xi, vi, s.dt, s.length, k.step.shear);
    } else {
      const double none[D] = {};
      const double* g = force.acts_at(xi) ? force.acceleration : none;
      double gained = 0.0;
      const int reflections = srd::stream_between_walls<D>(xi, vi, g, k.step.start_time, s.dt, s.walls,
                                                           s.wall_count, work ? &gained : nullptr);
      for (int a = 0; a < D; ++a)
        if (!(s.bounded & (1u << a))) xi[a] = srd::wrapped(xi[a], s.length[a]);
      if (work) work[i] = gained;
      if (hits) hits[i] = static_cast<std::uint8_t>(reflections);
    }
    std::int32_t grid[D];
    for (int a = 0; a < D; ++a) grid[a] = s.cells[a];
    cell[i] = srd::cell_of<D>(xi, k.step.shift, s.length, grid, k.step.shear, s.origin, s.bounded);
    if (image) image[i] = static_cast<std::int8_t>(srd::shear_image<D>(xi, k.step.shift, s.length));
  }
};

// start[c], end[c] of each occupied cell in the sorted keys (others stay 0).
struct CellBounds {
  std::size_t n;
  const std::uint32_t* sorted;
  std::uint32_t* start;
  std::uint32_t* end;
  GRANFLOW_HD void operator()(std::size_t q) const {
    const std::uint32_t c = sorted[q];
    if (q == 0 || sorted[q - 1] != c) start[c] = static_cast<std::uint32_t>(q);
    if (q + 1 == n || sorted[q + 1] != c) end[c] = static_cast<std::uint32_t>(q + 1);
  }
};

template <int D>
struct ReduceCell {
  StepConstants k;
  const std::uint32_t* order;
  const std::uint32_t* start;
  const std::uint32_t* end;
  const double* x;
  const double* v;
  const std::int8_t* image;
  std::uint32_t* count;
  std::uint32_t* ghosts;
  double* mass;
  double* velocity;
  double* theta;
  double* moment;
  GRANFLOW_HD void operator()(std::size_t c) const {
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
    srd::CellSums<D> sums{};
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
        const double offset = srd::moment_offset(s.particle_mass, y);
        for (int a = 0; a < D; ++a) m_moment[a] += offset * w[a];
        moment_mass += offset;
      }
    }
    const std::uint32_t added =
        srd::fill_cut_cell<D>(sums, members, c, c, k.cuts, k.cut_count, s.walls, s.cells, s.ghost_fill, k.step.end_time,
                              s.particle_mass, s.seed, k.step.step);
    if (ghosts) ghosts[c] = added;
    double drift[D], mean[D], t;
    srd::finish_sums<D>(sums, static_cast<double>(members + added), mean, t, drift);
    for (int a = 0; a < D; ++a) velocity[D * c + a] = mean[a];
    theta[c] = t;
    mass[c] = sums.mass;
    if (moment)
      for (int a = 0; a < D; ++a) moment[D * c + a] = m_moment[a] - moment_mass * drift[a];
  }
};

template <int D>
struct CellMatrix {
  StepConstants k;
  const std::uint32_t* count;
  const std::uint32_t* ghosts;
  const double* theta;
  const double* moment;
  double* matrices;
  double* transfer;
  double* clamped;  // per cell, summed afterwards
  GRANFLOW_HD void operator()(std::size_t c) const {
    const SrdDeviceSetup& s = k.setup;
    const srd::CellRotation<D> base(s.rotation);
    const double members = count[c] + (ghosts ? ghosts[c] : 0u);
    bool below_zero = false;
    double* matrix = matrices + D * D * c;
    srd::cell_collision_matrix<D>(base, s.granular, s.seed, k.step.step, c, members, theta[c], matrix, below_zero);
    clamped[c] = below_zero ? 1.0 : 0.0;
    if (transfer) transfer[c] = members >= 2 ? srd::collisional_transfer<D>(matrix, moment + D * c) : 0.0;
  }
};

template <int D>
struct Collide {
  StepConstants k;
  double* v;
  const std::uint32_t* cell;
  const std::int8_t* image;
  const double* matrices;
  const double* velocity;
  const std::uint32_t* ghosts;
  double* plain;
  double* ghosted;
  GRANFLOW_HD void operator()(std::size_t i) const {
    double* vi = v + D * i;
    const std::uint32_t c = cell[i];
    double before = 0.0, after = 0.0;
    if (plain)
      for (int a = 0; a < D; ++a) before += vi[a] * vi[a];
    srd::collide_particle<D>(vi, matrices + D * D * c, velocity + D * c,
                             image ? -image[i] * k.step.shear.velocity : 0.0);
    if (!plain) return;
    for (int a = 0; a < D; ++a) after += vi[a] * vi[a];
    const double change = 0.5 * (after - before);
    const bool with_ghosts = ghosts && ghosts[c] > 0;
    plain[i] = with_ghosts ? 0.0 : change;
    ghosted[i] = with_ghosts ? change : 0.0;
  }
};

// Per particle: m v_a (a < D), and m |v - V_cell|^2 as the cell sees it.
template <int D>
struct ThermostatTerms {
  StepConstants k;
  std::size_t n;
  const double* v;
  const std::uint32_t* cell;
  const std::int8_t* image;
  const double* velocity;
  double* terms;
  GRANFLOW_HD void operator()(std::size_t i) const {
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
};

struct Occupied {
  const std::uint32_t* count;
  double* out;
  GRANFLOW_HD void operator()(std::size_t c) const { out[c] = count[c] > 0 ? 1.0 : 0.0; }
};

template <int D>
struct Thermostat {
  StepConstants k;
  double* v;
  const std::uint32_t* cell;
  const std::int8_t* image;
  const double* velocity;
  double factor;
  double drift[3];
  GRANFLOW_HD void operator()(std::size_t i) const {
    const double image_velocity = image ? -image[i] * k.step.shear.velocity : 0.0;
    srd::thermostat_velocity<D>(v + D * i, velocity + D * cell[i], drift, factor, image_velocity);
  }
};

template <int D>
struct ShiftMeans {
  double* velocity;
  double drift[3];
  GRANFLOW_HD void operator()(std::size_t c) const {
    for (int a = 0; a < D; ++a) velocity[D * c + a] -= drift[a];
  }
};

// Gathers `width` values per particle into cell order.
template <class T>
struct Gather {
  int width;
  const std::uint32_t* order;
  const T* from;
  T* to;
  GRANFLOW_HD void operator()(std::size_t q) const {
    const std::size_t i = order[q];
    for (int a = 0; a < width; ++a) to[width * q + a] = from[width * i + a];
  }
};

// Fixed blocks of a column summed each in index order: the same partial
// sums on any back end and thread count.
constexpr std::size_t block_size = 1024;

struct BlockSum {
  const double* values;
  std::size_t count;
  double* partial;
  GRANFLOW_HD void operator()(std::size_t b) const {
    const std::size_t from = b * block_size;
    const std::size_t to = from + block_size < count ? from + block_size : count;
    double total = 0.0;
    for (std::size_t i = from; i < to; ++i) total += values[i];
    partial[b] = total;
  }
};

// Per block of particles: its wall reflections, and its particles that
// needed more than srd::most_reflections.
struct HitBlocks {
  const std::uint8_t* hits;
  std::size_t n;
  double* rows;  // blocks x 2
  GRANFLOW_HD void operator()(std::size_t b) const {
    double reflections = 0.0, stranded = 0.0;
    const std::size_t from = b * block_size;
    const std::size_t to = from + block_size < n ? from + block_size : n;
    for (std::size_t i = from; i < to; ++i) {
      reflections += hits[i];
      stranded += hits[i] == srd::most_reflections ? 1.0 : 0.0;
    }
    rows[2 * b] = reflections;
    rows[2 * b + 1] = stranded;
  }
};

// Per block of particles, per layer across `axis`: particles, sum of
// v[flow], of |v|^2 and of each v_a (width 3 + D).
template <int D>
struct LayerBlocks {
  const double* x;
  const double* v;
  std::size_t n;
  int axis, flow, layers;
  double* rows;  // blocks x layers x (3 + D)
  GRANFLOW_HD void operator()(std::size_t b) const {
    const int width = 3 + D;
    double* row = rows + b * static_cast<std::size_t>(layers * width);
    for (int k = 0; k < layers * width; ++k) row[k] = 0.0;
    const std::size_t from = b * block_size;
    const std::size_t to = from + block_size < n ? from + block_size : n;
    for (std::size_t i = from; i < to; ++i) {
      const double along = floor(x[D * i + axis]);
      const int k = along < 0.0 ? 0 : along >= layers - 1 ? layers - 1 : static_cast<int>(along);
      double* s = row + k * width;
      double v2 = 0.0;
      for (int a = 0; a < D; ++a) v2 += v[D * i + a] * v[D * i + a];
      s[0] += 1.0;
      s[1] += v[D * i + flow];
      s[2] += v2;
      for (int a = 0; a < D; ++a) s[3 + a] += v[D * i + a];
    }
  }
};

// Per block of particles: sums of vx vy, vy (y - L_y / 2) and vy^2.
template <int D>
struct StressBlocks {
  const double* x;
  const double* v;
  std::size_t n;
  double half;
  double* rows;  // blocks x 3
  GRANFLOW_HD void operator()(std::size_t b) const {
    double s[3] = {0, 0, 0};
    const std::size_t from = b * block_size;
    const std::size_t to = from + block_size < n ? from + block_size : n;
    for (std::size_t i = from; i < to; ++i) {
      const double vx = v[D * i], vy = v[D * i + 1];
      s[0] += vx * vy;
      s[1] += vy * (x[D * i + 1] - half);
      s[2] += vy * vy;
    }
    for (int k = 0; k < 3; ++k) rows[3 * b + k] = s[k];
  }
};

// The stages /profile names.
enum Stage {
  stream_stage,
  sort_stage,
  reduce_stage,
  collide_stage,
  thermostat_stage,
  reorder_stage,
  sums_stage,
  download_stage,
  stage_count
};
constexpr const char* stage_names[stage_count] = {
    "srd_device_step/stream_and_bin", "srd_device_step/sort",       "srd_device_step/reduce",
    "srd_device_step/collide",        "srd_device_step/thermostat", "srd_device_step/reorder",
    "srd_device_step/observer_sums",  "srd_device_step/download"};

// Times each stage: between CUDA events on a GPU (read once the step is
// done), by the wall clock on the host, where each algorithm returns when done.
class StageTimer {
 public:
  StageTimer() {
    for (int s = 0; s < stage_count; ++s) entries_[s].system = stage_names[s];
#if defined(__CUDACC__)
    for (auto& e : events_) check(cudaEventCreate(&e), "cudaEventCreate");
#endif
  }
  ~StageTimer() {
#if defined(__CUDACC__)
    for (auto& e : events_)
      if (e) cudaEventDestroy(e);
#endif
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

  void begin(Stage s) {
    timed_[s] = true;
#if defined(__CUDACC__)
    check(cudaEventRecord(events_[2 * s]), "cudaEventRecord");
#else
    started_[s] = std::chrono::steady_clock::now();
#endif
  }
  void finish(Stage s) {
#if defined(__CUDACC__)
    check(cudaEventRecord(events_[2 * s + 1]), "cudaEventRecord");
#else
    seconds_[s] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_[s]).count();
#endif
  }
  // After the step has finished.
  void collect() {
    for (int s = 0; s < stage_count; ++s) {
      if (!timed_[s]) continue;
#if defined(__CUDACC__)
      float ms = 0.0f;
      check(cudaEventElapsedTime(&ms, events_[2 * s], events_[2 * s + 1]), "cudaEventElapsedTime");
      seconds_[s] = 1e-3 * ms;
#endif
      entries_[s].calls += 1;
      entries_[s].total_seconds += seconds_[s];
      timed_[s] = false;
    }
  }
  std::vector<ProfileEntry> entries() const {
    std::vector<ProfileEntry> out;
    for (const ProfileEntry& e : entries_)
      if (e.calls > 0) out.push_back(e);
    return out;
  }

 private:
  ProfileEntry entries_[stage_count];
  bool timed_[stage_count] = {};
  double seconds_[stage_count] = {};
#if defined(__CUDACC__)
  cudaEvent_t events_[2 * stage_count] = {};
#else
  std::chrono::steady_clock::time_point started_[stage_count];
#endif
};

}  // namespace

const char* srd_device_backend() {
#if defined(__CUDACC__)
  return "cuda";
#else
  return "thrust_host";
#endif
}

std::string srd_device_unavailable() {
#if defined(__CUDACC__)
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess) return std::string("no usable CUDA driver or device (") + cudaGetErrorString(status) + ")";
  if (count == 0) return "no CUDA device found";
#endif
  return {};
}

struct SrdDevice::Impl {
  SrdDeviceSetup setup;
  std::size_t n = 0, cell_count = 0;
  Column<double> x, v, x_spare, v_spare;
  Column<std::uint32_t> cell, sorted_cell, order, start, end;
  Column<std::int8_t> image, image_spare;
  Column<std::uint32_t> count, ghosts;
  Column<double> mass, velocity, theta, matrices, moment, transfer;
  Column<double> work, plain, ghosted, terms, occupied, clamped;
  Column<std::uint8_t> hits;
  Column<double> partial;  // block sums
  std::vector<double> partial_host;
  StageTimer timer;
  std::uint64_t steps_done = 0;

  // Sum of `count_in` doubles from `in`, the same on every back end.
  double sum(const double* in, std::size_t count_in) {
    if (count_in == 0) return 0.0;
    const std::size_t blocks = (count_in + block_size - 1) / block_size;
    if (partial.size() < blocks) partial.resize(blocks);
    for_each_index(blocks, BlockSum{in, count_in, raw(partial)});
    partial_host.resize(blocks);
    thrust::copy(partial.begin(), partial.begin() + static_cast<std::ptrdiff_t>(blocks), partial_host.begin());
    double total = 0.0;
    for (double p : partial_host) total += p;
    return total;
  }

  // Blocks of `width` numbers each, summed in block order on the host.
  std::vector<double> sum_rows(std::size_t blocks, std::size_t width) {
    partial_host.resize(blocks * width);
    thrust::copy(partial.begin(), partial.begin() + static_cast<std::ptrdiff_t>(blocks * width), partial_host.begin());
    std::vector<double> total(width, 0.0);
    for (std::size_t b = 0; b < blocks; ++b)
      for (std::size_t k = 0; k < width; ++k) total[k] += partial_host[b * width + k];
    return total;
  }

  template <int D>
  void observer_sums(const SrdSumRequests& requests, SrdDeviceReport& report) {
    const std::size_t blocks = (n + block_size - 1) / block_size;
    for (const SrdLayerRequest& r : requests.layers) {
      const std::size_t width = static_cast<std::size_t>(r.layers) * (3 + D);
      if (partial.size() < blocks * width) partial.resize(blocks * width);
      for_each_index(blocks, LayerBlocks<D>{raw(x), raw(v), n, r.axis, r.flow, r.layers, raw(partial)});
      report.layer_sums.push_back(sum_rows(blocks, width));
    }
    if (requests.stress) {
      if (partial.size() < blocks * 3) partial.resize(blocks * 3);
      for_each_index(blocks, StressBlocks<D>{raw(x), raw(v), n, 0.5 * setup.length[1], raw(partial)});
      const auto s = sum_rows(blocks, 3);
      for (int k = 0; k < 3; ++k) report.stress_sums[k] = s[static_cast<std::size_t>(k)];
      report.transfer_sum = sum(raw(transfer), transfer.size());
    }
  }

  template <int D>
  SrdDeviceReport step(const SrdDeviceStep& in, const SrdSumRequests& sums);
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
  try {
    d.x.resize(dim * n);
    d.v.resize(dim * n);
    d.x_spare.resize(dim * n);
    d.v_spare.resize(dim * n);
    d.cell.resize(n);
    d.sorted_cell.resize(n);
    d.order.resize(n);
    if (setup.wall_count > 0) d.hits.resize(n);
    d.start.resize(cells);
    d.end.resize(cells);
    d.count.resize(cells);
    if (setup.wall_count > 0) d.ghosts.resize(cells);
    d.mass.resize(cells);
    d.velocity.resize(dim * cells);
    d.theta.resize(cells);
    d.matrices.resize(dim * dim * cells);
    d.clamped.resize(cells);
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
  } catch (const std::exception& error) {
    throw std::runtime_error(std::string("cannot hold the SRD step's columns in the back end's memory (") +
                             srd_device_backend() + "): " + error.what());
  }
}

SrdDevice::~SrdDevice() = default;

void SrdDevice::upload(const double* x, const double* v) {
  Impl& d = *impl_;
  thrust::copy(x, x + d.x.size(), d.x.begin());
  thrust::copy(v, v + d.v.size(), d.v.begin());
}

template <int D>
SrdDeviceReport SrdDevice::Impl::step(const SrdDeviceStep& in, const SrdSumRequests& sums) {
  StepConstants k{};
  k.setup = setup;
  k.step = in;
  // The layers the no-slip walls with ghosts cut at the step's end, as the CPU reduction finds them.
  const double time = in.end_time;
  k.cut_count = srd::find_cut_layers(setup.walls, setup.wall_count, setup.cells, in.shift, setup.origin, time, k.cuts);
  std::int8_t* img = raw(image);
  std::uint32_t* ghost_counts = raw(ghosts);

  timer.begin(stream_stage);
  for_each_index(n, Stream<D>{k, raw(x), raw(v), raw(cell), img, raw(work), raw(hits)});
  timer.finish(stream_stage);

  // The stable sort keeps particles of a cell in storage order, as the
  // CPU's counting sort does.
  timer.begin(sort_stage);
  thrust::copy(thrust::device, cell.begin(), cell.end(), sorted_cell.begin());
  thrust::sequence(thrust::device, order.begin(), order.end());
  thrust::stable_sort_by_key(thrust::device, sorted_cell.begin(), sorted_cell.end(), order.begin());
  thrust::fill(thrust::device, start.begin(), start.end(), 0u);
  thrust::fill(thrust::device, end.begin(), end.end(), 0u);
  for_each_index(n, CellBounds{n, raw(sorted_cell), raw(start), raw(end)});
  timer.finish(sort_stage);

  // At reorderings the columns are gathered into cell order, and the order
  // becomes the identity.
  if (setup.reorder_interval > 0 && in.step % setup.reorder_interval == 0) {
    timer.begin(reorder_stage);
    for_each_index(n, Gather<double>{D, raw(order), raw(x), raw(x_spare)});
    for_each_index(n, Gather<double>{D, raw(order), raw(v), raw(v_spare)});
    x.swap(x_spare);
    v.swap(v_spare);
    if (img) {
      for_each_index(n, Gather<std::int8_t>{1, raw(order), raw(image), raw(image_spare)});
      image.swap(image_spare);
      img = raw(image);
    }
    thrust::copy(thrust::device, sorted_cell.begin(), sorted_cell.end(), cell.begin());
    thrust::sequence(thrust::device, order.begin(), order.end());
    timer.finish(reorder_stage);
  }

  timer.begin(reduce_stage);
  for_each_index(cell_count, ReduceCell<D>{k, raw(order), raw(start), raw(end), raw(x), raw(v), img, raw(count),
                                           ghost_counts, raw(mass), raw(velocity), raw(theta), raw(moment)});
  timer.finish(reduce_stage);

  timer.begin(collide_stage);
  for_each_index(cell_count, CellMatrix<D>{k, raw(count), ghost_counts, raw(theta), raw(moment), raw(matrices),
                                           raw(transfer), raw(clamped)});
  for_each_index(n, Collide<D>{k, raw(v), raw(cell), img, raw(matrices), raw(velocity), ghost_counts, raw(plain),
                               raw(ghosted)});
  SrdDeviceReport report;
  if (setup.record_energy) {
    report.wall_work = setup.particle_mass * sum(raw(work), n);
    report.collision_energy = setup.particle_mass * sum(raw(plain), n);
    report.ghost_cell_energy = setup.particle_mass * sum(raw(ghosted), n);
  }
  timer.finish(collide_stage);

  if (setup.thermostat > 0.0) {
    timer.begin(thermostat_stage);
    for_each_index(n, ThermostatTerms<D>{k, n, raw(v), raw(cell), img, raw(velocity), raw(terms)});
    for_each_index(cell_count, Occupied{raw(count), raw(occupied)});
    double s[D + 1];
    for (int a = 0; a <= D; ++a) s[a] = sum(raw(terms) + static_cast<std::size_t>(a) * n, n);
    const double occupied_cells = sum(raw(occupied), cell_count);
    double drift[3] = {0, 0, 0};
    if (setup.thermostat_removes_drift)
      for (int a = 0; a < D; ++a) drift[a] = s[a] / (setup.particle_mass * static_cast<double>(n));
    const double thermal = s[D], dof = D * (static_cast<double>(n) - occupied_cells);
    if (thermal > 0.0 && dof > 0.0) {
      const double factor = std::sqrt(setup.thermostat * dof / thermal);
      for_each_index(n,
                     Thermostat<D>{k, raw(v), raw(cell), img, raw(velocity), factor, {drift[0], drift[1], drift[2]}});
      for_each_index(cell_count, ShiftMeans<D>{raw(velocity), {drift[0], drift[1], drift[2]}});
    }
    timer.finish(thermostat_stage);
  }

  if (!sums.layers.empty() || sums.stress) {
    timer.begin(sums_stage);
    observer_sums<D>(sums, report);
    timer.finish(sums_stage);
  }
  if (!hits.empty()) {
    const std::size_t blocks = (n + block_size - 1) / block_size;
    if (partial.size() < 2 * blocks) partial.resize(2 * blocks);
    for_each_index(blocks, HitBlocks{raw(hits), n, raw(partial)});
    const auto counts = sum_rows(blocks, 2);
    report.reflections = static_cast<std::uint64_t>(counts[0]);
    report.stranded = static_cast<std::uint64_t>(counts[1]);
  }
  report.clamped_cells = static_cast<std::uint64_t>(sum(raw(clamped), cell_count));
#if defined(__CUDACC__)
  check(cudaDeviceSynchronize(), "SRD step");
#endif
  timer.collect();
  ++steps_done;
  return report;
}

SrdDeviceReport SrdDevice::step(const SrdDeviceStep& step, const SrdSumRequests& sums) {
  return impl_->setup.dimension == 2 ? impl_->step<2>(step, sums) : impl_->step<3>(step, sums);
}

void SrdDevice::download(const SrdHostArrays& host) {
  Impl& d = *impl_;
  d.timer.begin(download_stage);
  copy_to_host(host.x, d.x, "copy of positions to the host");
  copy_to_host(host.v, d.v, "copy of velocities to the host");
  copy_to_host(host.cell, d.cell, "copy of cells to the host");
  copy_to_host(host.image, d.image, "copy of images to the host");
  copy_to_host(host.count, d.count, "copy of cell counts to the host");
  copy_to_host(host.ghosts, d.ghosts, "copy of ghost counts to the host");
  copy_to_host(host.mass, d.mass, "copy of cell masses to the host");
  copy_to_host(host.velocity, d.velocity, "copy of cell velocities to the host");
  copy_to_host(host.theta, d.theta, "copy of cell temperatures to the host");
  copy_to_host(host.transfer, d.transfer, "copy of collisional transfers to the host");
  d.timer.finish(download_stage);
#if defined(__CUDACC__)
  check(cudaDeviceSynchronize(), "copy to the host");
#endif
  d.timer.collect();
}

std::vector<ProfileEntry> SrdDevice::profile() const { return impl_->timer.entries(); }

std::size_t SrdDevice::bytes() const {
  const Impl& d = *impl_;
  std::size_t total = 0;
  for (const auto* b : {&d.x, &d.v, &d.x_spare, &d.v_spare, &d.mass, &d.velocity, &d.theta, &d.matrices, &d.moment,
                        &d.transfer, &d.work, &d.plain, &d.ghosted, &d.terms, &d.occupied, &d.clamped, &d.partial})
    total += b->size() * sizeof(double);
  for (const auto* b : {&d.cell, &d.sorted_cell, &d.order, &d.start, &d.end, &d.count, &d.ghosts})
    total += b->size() * sizeof(std::uint32_t);
  return total + d.image.size() + d.image_spare.size() + d.hits.size();
}

}  // namespace granflow::device
