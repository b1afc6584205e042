#pragma once
// Profiles against the coordinate normal to the walls, in layers one cell
// thick on the unshifted grid: velocity_profile (the mean velocity along the
// flow axis: x, or y where the walls are perpendicular to x),
// density_profile (particles per cell volume) and temperature_profile (the
// layer's kinetic temperature about its own mean velocity). A sampler adds
// every step after the warm-up; the observer writes the averages over the
// steps since its last output, and keeps the average since the warm-up for
// the scenario's fit.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/run.hpp"
#include "systems/srd/shear_band.hpp"
#include "systems/srd/srd_cells.hpp"
#include "systems/srd/srd_step_sums.hpp"

namespace granflow::srd {

inline const SystemDescription sample_srd_profiles_description{
    "sample_srd_profiles", "velocity, density and temperature in layers across the walls, every step after the warm-up"};
inline const SystemDescription observe_srd_profiles_description{
    "observe_srd_profiles", "velocity_profile, density_profile, temperature_profile: averages since the last output"};

// Per layer: particles, sum of the flow velocity, sum of |v|^2 and of each
// velocity component (for the layer's mean), over the samples of a block and
// since the warm-up.
class ProfileSums : public Stateful {
 public:
  // Shared by the sampler and the observer (not a World resource): the key
  // of their access declarations, which orders them.
  static constexpr const char* key = "srd_profile_sums";
  ProfileSums(int layers, int dimension) : layers_(layers), dimension_(dimension) {
    block_.assign(static_cast<std::size_t>(layers) * width(), 0.0);
    total_ = block_;
  }
  std::size_t width() const { return 3 + static_cast<std::size_t>(dimension_); }
  int layers() const { return layers_; }

  // One step's sums per layer, `width()` numbers each.
  void add(const std::vector<double>& step) {
    for (std::size_t k = 0; k < step.size(); ++k) {
      block_[k] += step[k];
      total_[k] += step[k];
    }
    ++block_samples_;
    ++total_samples_;
  }

  struct Profiles {
    std::vector<double> velocity, density, temperature;
  };
  // The block's averages (and starts a new block), or those since the warm-up.
  Profiles take_block(double layer_volume, double mass) {
    Profiles out = averages(block_, block_samples_, layer_volume, mass);
    if (block_samples_ > 0) block_velocities_.insert(block_velocities_.end(), out.velocity.begin(), out.velocity.end());
    std::fill(block_.begin(), block_.end(), 0.0);
    block_samples_ = 0;
    return out;
  }
  Profiles overall(double layer_volume, double mass) const { return averages(total_, total_samples_, layer_volume, mass); }
  std::int64_t samples() const { return total_samples_; }
  // The velocity profiles of the blocks taken so far, one after another.
  const std::vector<double>& block_velocities() const { return block_velocities_; }

  StateMap save_state() const override {
    return {{"block", block_}, {"total", total_}, {"block_velocities", block_velocities_},
            {"samples", {static_cast<double>(block_samples_), static_cast<double>(total_samples_)}}};
  }
  void restore_state(const StateMap& state) override {
    if (state.at("block").size() != block_.size() || state.at("total").size() != total_.size() ||
        state.at("samples").size() != 2)
      throw std::invalid_argument("checkpoint profile sums have the wrong sizes");
    block_velocities_ = state.at("block_velocities");
    block_ = state.at("block");
    total_ = state.at("total");
    block_samples_ = static_cast<std::int64_t>(state.at("samples")[0]);
    total_samples_ = static_cast<std::int64_t>(state.at("samples")[1]);
  }

 private:
  Profiles averages(const std::vector<double>& sums, std::int64_t samples, double layer_volume, double mass) const {
    Profiles out;
    const std::size_t w = width();
    for (int k = 0; k < layers_; ++k) {
      const double* s = &sums[static_cast<std::size_t>(k) * w];
      const double count = s[0];
      out.density.push_back(samples > 0 ? count / (static_cast<double>(samples) * layer_volume) : 0.0);
      out.velocity.push_back(count > 0 ? s[1] / count : 0.0);
      double mean2 = 0.0;
      for (int a = 0; a < dimension_; ++a) mean2 += (s[3 + a] / std::max(count, 1.0)) * (s[3 + a] / std::max(count, 1.0));
      out.temperature.push_back(count > 0 ? mass * (s[2] / count - mean2) / dimension_ : 0.0);
    }
    return out;
  }

  int layers_, dimension_;
  std::vector<double> block_, total_, block_velocities_;
  std::int64_t block_samples_ = 0, total_samples_ = 0;
};

template <int D>
using SrdProfileSamplerBase = SystemOf<Reads<Position<D>, Velocity<D>, Clock>, Writes<ProfileSums, SrdStepSums<D>>>;

template <int D>
class SrdProfileSampler : public SrdProfileSamplerBase<D> {
 public:
  using View = typename SrdProfileSamplerBase<D>::View;
  // axis: the walls' normal; flow: the velocity component profiled.
  SrdProfileSampler(int axis, int flow, std::shared_ptr<ProfileSums> sums) : axis_(axis), flow_(flow), sums_(std::move(sums)) {}

  std::string name() const override { return "sample_srd_profiles"; }
  bool reads_device_state(const World& world) const override { return !device_.ready(world); }
  // The step's sums are the ranks' totals; its own pass is totalled likewise.
  bool observes_by_rank() const override { return true; }

  void run_on(View view) override {
    if (const auto* sums = device_.ready(view)) {
      sums_->add(device_.layers(*sums));
      return;
    }
    const int layers = sums_->layers();
    device_.ask(view, {axis_, flow_, layers});  // from the next step on, the device step sums
    const auto& x = view.template read<Position<D>>();
    const auto& v = view.template read<Velocity<D>>();
    const std::size_t w = sums_->width();
    std::vector<double> step(static_cast<std::size_t>(layers) * w, 0.0);
    // Serial: a fixed order, so the sums do not depend on the thread count.
    for (std::size_t i = 0; i < view.size(); ++i) {
      const int k = std::clamp(static_cast<int>(std::floor(x[i][axis_])), 0, layers - 1);
      double* s = &step[static_cast<std::size_t>(k) * w];
      s[0] += 1.0;
      s[1] += v[i][flow_];
      s[2] += v[i].squaredNorm();
      for (int a = 0; a < D; ++a) s[3 + a] += v[i][a];
    }
    sums_->add(view.part().total(step));
  }

 private:
  int axis_, flow_;
  std::shared_ptr<ProfileSums> sums_;
  StepSumsRequest<D> device_;
};

template <int D>
class SrdProfileObserver : public SystemOf<Reads<>, Writes<ProfileSums>> {
 public:
  // band: also band_width and band_contrast of each density profile (shear_band.hpp).
  SrdProfileObserver(double layer_volume, double mass, std::shared_ptr<ProfileSums> sums, bool band = false)
      : layer_volume_(layer_volume), mass_(mass), sums_(std::move(sums)), band_(band) {}

  std::string name() const override { return "observe_srd_profiles"; }
  bool observes_by_rank() const override { return true; }  // the sums are the same on every rank
  Access access() const override {
    Access access = View::access();
    if (band_) access.writes_observable("band_width", unit::length).writes_observable("band_contrast", unit::none);
    return access
        .writes_observable("velocity_profile", unit::velocity)
        .writes_observable("density_profile", "L-" + std::to_string(D))
        .writes_observable("temperature_profile", unit::energy);
  }

  void run_on(View view) override {
    auto profiles = sums_->take_block(layer_volume_, mass_);
    auto& store = view.observables();
    if (band_) {
      const ShearBand band = shear_band(profiles.density);
      store.set("band_width", band.width);
      store.set("band_contrast", band.contrast);
    }
    store.set("velocity_profile", std::move(profiles.velocity));
    store.set("density_profile", std::move(profiles.density));
    store.set("temperature_profile", std::move(profiles.temperature));
  }

 private:
  double layer_volume_, mass_;
  std::shared_ptr<ProfileSums> sums_;
  bool band_;
};

// The layer volume of the profiles across `axis` of a box of `cells`.
template <int D>
double layer_volume(const std::array<std::int32_t, D>& cells, int axis) {
  double volume = 1.0;
  for (int a = 0; a < D; ++a)
    if (a != axis) volume *= cells[a];
  return volume;
}

// The profiles across `axis` of a box of `cells`: sampled every step after
// `warmup_steps`, written every `every_steps` after it; the sums (kept in
// checkpoints as "profiles") hold the average since the warm-up. `flow`:
// the velocity component profiled; `band`: the shear-band measures too;
// `stride`: steps between samples (1: every step).
template <int D>
std::shared_ptr<ProfileSums> add_layer_profiles(Run& run, const std::array<std::int32_t, D>& cells, int axis,
                                                std::int64_t warmup_steps, std::int64_t every_steps, int flow = 0,
                                                bool band = false, std::int64_t stride = 1) {
  auto sums = std::make_shared<ProfileSums>(cells[axis], D);
  run.keep("profiles", *sums);
  run.observe<SrdProfileSampler<D>>(std::make_shared<EverySteps>(stride, warmup_steps + stride), axis, flow, sums);
  run.observe<SrdProfileObserver<D>>(std::make_shared<EverySteps>(every_steps, warmup_steps + every_steps),
                                     layer_volume<D>(cells, axis), 1.0, sums, band);
  return sums;
}

// The densest layer of the profiles averaged since the warm-up, against
// the lowest one (a driven floor's): attributes dense_layer_height (its
// centre, in cells), dense_layer_density (over the mean `n0`),
// floor_layer_temperature and dense_layer_temperature.
inline void write_densest_layer(H5mdFile& file, const ProfileSums& sums, double layer_volume, double n0) {
  const auto overall = sums.overall(layer_volume, 1.0);
  if (sums.samples() == 0) return;
  const auto densest = static_cast<std::size_t>(std::max_element(overall.density.begin(), overall.density.end()) -
                                                overall.density.begin());
  const double height = static_cast<double>(densest) + 0.5;
  file.write_attribute("/observables", "dense_layer_height", height);
  file.write_attribute("/observables", "dense_layer_density", overall.density[densest] / n0);
  file.write_attribute("/observables", "floor_layer_temperature", overall.temperature[0]);
  file.write_attribute("/observables", "dense_layer_temperature", overall.temperature[densest]);
  spdlog::info("profiles over {} steps: densest layer at height {:.1f} of {} ({:.3g} n0, temperature {:.4g}); lowest "
               "layer {:.3g} n0 at temperature {:.4g}",
               sums.samples(), height, overall.density.size(), overall.density[densest] / n0,
               overall.temperature[densest], overall.density[0] / n0, overall.temperature[0]);
}

}  // namespace granflow::srd
