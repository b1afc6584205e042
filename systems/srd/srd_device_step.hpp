#pragma once
// The whole SRD step on the device step's back end (srd.device = "cuda" on
// an NVIDIA GPU, "thrust_host" on Thrust's oneTBB host back end): one system
// in place of streaming, grid shift, binning, reduction, rotation and
// thermostat, with the particle columns resident in the back end's memory
// (systems/srd/srd_device.hpp). The host computes what the CPU systems compute
// from the clock alone (the step number, the grid shift, the Lees-Edwards
// state) and copies the state back only when observers or a checkpoint
// read it (synchronise_host): the particles and this step's cell data, in
// the device's storage order, which is the CPU's as both put the particles
// in cell order at the same steps.
//
// Only in builds with a device step (the granflow_srd_device library);
// srd_device_backends.hpp refuses the key elsewhere.

#include <spdlog/spdlog.h>

#include <array>
#include <memory>
#include <numbers>
#include <vector>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/srd/grid_shift.hpp"
#include "systems/srd/rotation.hpp"
#include "systems/srd/srd_cells.hpp"
#include "systems/srd/srd_device.hpp"
#include "systems/srd/srd_step_sums.hpp"
#include "systems/srd/streaming.hpp"

namespace granflow::srd {

inline const SystemDescription srd_device_step_description{
    "srd_device_step",
    "the SRD step on a GPU or Thrust's host back end: streaming to thermostat, the columns resident there"};

struct DeviceStepParameters {
  double dt = 1.0;
  double shear_rate = 0.0;
  BodyForce<3> force;  // its first D entries
  RotationParameters rotation;
  bool grid_shift = true;
  std::uint64_t seed = 0;
  std::uint64_t reorder_interval = 20;
  double thermostat = 0.0;
  bool thermostat_removes_drift = true;
};

template <int D>
using SrdDeviceStepBase =
    SystemOf<Reads<>, Writes<Position<D>, Velocity<D>, Clock, SrdCells<D>, SrdStepSums<D>, RunControl>>;

// The device keeps the particles; synchronise_host brings them back when a
// system that reads them runs.
template <int D>
class SrdDeviceStep : public SrdDeviceStepBase<D> {
 public:
  SrdDeviceStep(const DeviceStepParameters& p, const SrdCells<D>& cells, std::size_t particles) : p_(p) {
    device::SrdDeviceSetup s;
    s.dimension = D;
    for (int a = 0; a < D; ++a) {
      s.cells[a] = cells.cells[a];
      s.length[a] = cells.length[a];
      s.origin[a] = cells.origin[a];
    }
    s.bounded = cells.bounded;
    s.wall_count = static_cast<int>(cells.walls.size());
    for (int w = 0; w < s.wall_count; ++w) s.walls[w] = cells.walls[static_cast<std::size_t>(w)];
    s.force = p.force;
    s.dt = p.dt;
    s.particle_mass = cells.particle_mass;
    s.ghost_fill = cells.ghost_fill;
    s.seed = p.seed;
    s.rotation = CellRotation<3>(rotation_base<D>(p.rotation));
    s.granular = granular_parameters(p.rotation);
    s.shear = D >= 2 && p.shear_rate != 0.0;
    s.record_moments = cells.record_moments && p.rotation.record_transfer;
    s.record_energy = cells.record_energy;
    s.thermostat = p.thermostat;
    s.thermostat_removes_drift = p.thermostat_removes_drift;
    s.reorder_interval = p.reorder_interval;
    device_ = std::make_unique<device::SrdDevice>(s, particles);
    spdlog::info("SRD device step ({}): {:.3g} GB for {} particles", device::srd_device_backend(),
                 device_->bytes() / 1e9, particles);
  }

  using View = typename SrdDeviceStepBase<D>::View;
  std::string name() const override { return "srd_device_step"; }

  void run_on(View view) override {
    auto& clock = view.template write<Clock>();
    auto& cells = view.template write<SrdCells<D>>();
    // Observers' sums, where the World offers them (srd_step_sums.hpp).
    SrdStepSums<D>* sums = view.template has<SrdStepSums<D>>() ? &view.template write<SrdStepSums<D>>() : nullptr;
    device::SrdSumRequests requests;
    if (sums) {
      for (const LayerSumsRequest& r : sums->layer_requests) requests.layers.push_back({r.axis, r.flow, r.layers});
      requests.stress = sums->stress_requested;
    }
    if (!uploaded_) {  // the initial state, or the one a checkpoint restored
      device_->upload(view.template read<Position<D>>().data()->data(), view.template read<Velocity<D>>().data()->data());
      uploaded_ = true;
    }
    device::SrdDeviceStep in;
    in.start_time = clock.time;
    clock.advance(p_.dt);
    in.step = static_cast<std::uint64_t>(clock.step);
    in.end_time = clock.time;
    SrdStreaming<D>::set_shear(cells, p_.shear_rate, clock.time);
    in.shear = cells.shear;
    SrdGridShift<D>::draw(cells.shift, p_.seed, in.step, p_.grid_shift);
    for (int a = 0; a < D; ++a) in.shift[a] = cells.shift[a];
    device::SrdDeviceReport report = device_->step(in, requests);
    if (sums) {
      sums->step = clock.step;
      sums->layers = std::move(report.layer_sums);
      for (int k = 0; k < 3; ++k) sums->stress[k] = report.stress_sums[k];
      sums->transfer = report.transfer_sum;
    }
    cells.wall_reflections += report.reflections;
    if (report.stranded > 0)
      view.template write<RunControl>().fail(stranded_failure(clock.time, clock.step, report.stranded, p_.dt));
    cells.clamped_cells = report.clamped_cells;
    cells.step_wall_work = report.wall_work;
    cells.step_collision_energy = report.collision_energy;
    cells.step_ghost_cell_energy = report.ghost_cell_energy;
    if (report.clamped_cells > 0 && !warned_) {
      warned_ = true;
      warn_clamped_cells(static_cast<std::int64_t>(in.step), report.clamped_cells);
    }
    host_current_ = false;
  }

  void synchronise_host(World& world) override {
    if (host_current_ || !uploaded_) return;
    auto& cells = world.resource<SrdCells<D>>();
    cells.image.resize(D >= 2 && cells.shear.velocity != 0.0 ? world.size() : 0);
    if (cells.record_moments) cells.moment.resize(cells.cell_count());
    device::SrdHostArrays host;
    host.x = world.component<Position<D>>().data()->data();
    host.v = world.component<Velocity<D>>().data()->data();
    host.cell = cells.cell.data();
    host.image = cells.image.empty() ? nullptr : cells.image.data();
    host.count = cells.count.data();
    host.ghosts = cells.ghosts.empty() ? nullptr : cells.ghosts.data();
    host.mass = cells.mass.data();
    host.velocity = cells.velocity.data()->data();
    host.theta = cells.theta.data();
    host.transfer = cells.record_moments && p_.rotation.record_transfer ? cells.transfer.data() : nullptr;
    device_->download(host);
    host_current_ = true;
  }

  std::vector<ProfileEntry> device_profile() const override { return device_->profile(); }

 private:
  DeviceStepParameters p_;
  std::unique_ptr<device::SrdDevice> device_;
  bool uploaded_ = false;
  bool host_current_ = true;
  bool warned_ = false;
};

}  // namespace granflow::srd
