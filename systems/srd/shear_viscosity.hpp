#pragma once
// Shear viscosity of a Lees-Edwards sheared SRD fluid, from the off-diagonal
// stress split into its two parts (Kikuchi et al. 2003):
//   kinetic, the x-momentum the streaming carries across planes of constant
//   y: sigma_kin = -rho <dv_x dv_y> + rho (gamma_dot dt / 2) <dv_y^2>, with
//   dv the velocity about the measured profile, just after the collision (a
//   particle that crosses a plane going up started below it, where the flow
//   is slower by gamma_dot times its distance: hence the second term, which
//   is positive; the printed -1/2 of some derivations is a sign slip);
//   collisional, the x-momentum the rotations move across such planes inside
//   each cell: sigma_coll = -(1 / (V dt)) sum m (dv_x of the collision) (y - y_cell).
// Each viscosity is sigma / (rho gamma_dot) with gamma_dot the slope of the
// measured profile <v_x>(y), fitted away from the two slabs next to the
// Lees-Edwards plane. The sampler runs every step after a warm-up; the
// reporter writes the averages so far (with standard errors from blocks of
// `block` steps) at output times.

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/observables/least_squares.hpp"
#include "systems/srd/srd_cells.hpp"
#include "systems/srd/srd_step_sums.hpp"

namespace granflow::srd {

inline const SystemDescription sample_srd_stress_description{
    "sample_srd_stress", "kinetic and collisional shear stress and the velocity profile of each step after the warm-up"};
inline const SystemDescription observe_srd_viscosity_description{
    "observe_srd_viscosity", "shear_rate_measured, viscosity_kinetic and viscosity_collisional so far, with standard errors"};

// Sums over the sampled steps, and the same per block for the errors.
class ShearStress : public Stateful {
 public:
  // Shared by the sampler and the observer (not a World resource): the key
  // of their access declarations, which orders them.
  static constexpr const char* key = "srd_shear_stress";
  ShearStress(int slabs, double dt, std::int64_t block) : profile_(slabs, 0.0), counts_(slabs, 0.0), dt_(dt), block_(block) {}

  // One step's per-particle means (mass-weighted) and the profile.
  void add(double vxvy, double vy_y, double vy2, double mass, double transfer, const std::vector<double>& slab_vx,
           const std::vector<double>& slab_count) {
    const double values[5] = {vxvy, vy_y, vy2, mass, transfer};
    for (int k = 0; k < 5; ++k) {
      total_[k] += values[k];
      block_sum_[k] += values[k];
    }
    for (std::size_t j = 0; j < profile_.size(); ++j) {
      profile_[j] += slab_vx[j];
      counts_[j] += slab_count[j];
    }
    ++samples_;
    if (++in_block_ == block_) {
      for (int k = 0; k < 5; ++k) blocks_.push_back(block_sum_[k] / static_cast<double>(block_));
      for (double& s : block_sum_) s = 0.0;
      in_block_ = 0;
    }
  }

  std::int64_t samples() const { return samples_; }
  // The particles a sample counted (every sample counts them all).
  double particles() const {
    double all = 0.0;
    for (const double c : counts_) all += c;
    return samples_ > 0 ? all / static_cast<double>(samples_) : 0.0;
  }

  // Least-squares slope of the slab means, leaving out the slab on each side of the shear plane.
  double measured_shear_rate() const {
    LineFit fit;
    for (std::size_t j = 1; j + 1 < profile_.size(); ++j)
      if (counts_[j] > 0) fit.add(static_cast<double>(j) + 0.5, profile_[j] / counts_[j]);
    return fit.determinant() > 0 ? fit.slope() : 0.0;
  }

  struct Viscosities {
    double kinetic = 0, kinetic_error = 0, collisional = 0, collisional_error = 0;
  };
  // n: particles (the collisional transfer is a sum over them).
  Viscosities viscosities(double rate, double particles) const {
    Viscosities out;
    if (samples_ == 0 || rate == 0.0) return out;
    const auto kinetic = [&](const double* s) { return -(s[0] - rate * s[1]) / (s[3] * rate) + 0.5 * dt_ * s[2] / s[3]; };
    const auto collisional = [&](const double* s) { return -s[4] / (particles * s[3] * dt_ * rate); };
    double mean[5];
    for (int k = 0; k < 5; ++k) mean[k] = total_[k] / static_cast<double>(samples_);
    out.kinetic = kinetic(mean);
    out.collisional = collisional(mean);
    const std::size_t b = blocks_.size() / 5;
    if (b >= 2) {
      double sk = 0, skk = 0, sc = 0, scc = 0;
      for (std::size_t k = 0; k < b; ++k) {
        const double vk = kinetic(&blocks_[5 * k]), vc = collisional(&blocks_[5 * k]);
        sk += vk;
        skk += vk * vk;
        sc += vc;
        scc += vc * vc;
      }
      const double nb = static_cast<double>(b);
      out.kinetic_error = std::sqrt(std::max(0.0, (skk / nb - (sk / nb) * (sk / nb)) / (nb - 1)));
      out.collisional_error = std::sqrt(std::max(0.0, (scc / nb - (sc / nb) * (sc / nb)) / (nb - 1)));
    }
    return out;
  }

  // kT_yy = <m v_y^2> over the sampled steps (the temperature the streaming
  // term of the viscosity carries), with its standard error from the blocks.
  std::pair<double, double> temperature_yy() const {
    if (samples_ == 0) return {std::nan(""), std::nan("")};
    const double mean = total_[2] / static_cast<double>(samples_);
    const std::size_t b = blocks_.size() / 5;
    if (b < 2) return {mean, std::nan("")};
    double s = 0, ss = 0;
    for (std::size_t k = 0; k < b; ++k) {
      s += blocks_[5 * k + 2];
      ss += blocks_[5 * k + 2] * blocks_[5 * k + 2];
    }
    const double nb = static_cast<double>(b);
    return {mean, std::sqrt(std::max(0.0, (ss / nb - (s / nb) * (s / nb)) / (nb - 1)))};
  }

  StateMap save_state() const override {
    StateMap out;
    out["total"] = {total_, total_ + 5};
    out["block_sum"] = {block_sum_, block_sum_ + 5};
    out["blocks"] = blocks_;
    out["profile"] = profile_;
    out["counts"] = counts_;
    out["counters"] = {static_cast<double>(samples_), static_cast<double>(in_block_)};
    return out;
  }
  void restore_state(const StateMap& state) override {
    const auto& total = state.at("total");
    const auto& block_sum = state.at("block_sum");
    const auto& counters = state.at("counters");
    if (total.size() != 5 || block_sum.size() != 5 || counters.size() != 2 || state.at("blocks").size() % 5 != 0 ||
        state.at("profile").size() != profile_.size() || state.at("counts").size() != counts_.size())
      throw std::invalid_argument("checkpoint shear-stress sums have the wrong sizes");
    std::copy(total.begin(), total.end(), total_);
    std::copy(block_sum.begin(), block_sum.end(), block_sum_);
    blocks_ = state.at("blocks");
    profile_ = state.at("profile");
    counts_ = state.at("counts");
    samples_ = static_cast<std::int64_t>(counters[0]);
    in_block_ = static_cast<std::int64_t>(counters[1]);
  }

 private:
  double total_[5] = {0, 0, 0, 0, 0};
  double block_sum_[5] = {0, 0, 0, 0, 0};
  std::vector<double> blocks_;
  std::vector<double> profile_, counts_;
  double dt_;
  std::int64_t block_;
  std::int64_t samples_ = 0;
  std::int64_t in_block_ = 0;
};

template <int D>
using ShearStressSamplerBase =
    SystemOf<Reads<Position<D>, Velocity<D>, Mass, SrdCells<D>, Clock>, Writes<ShearStress, SrdStepSums<D>>>;

template <int D>
class ShearStressSampler : public ShearStressSamplerBase<D> {
 public:
  using View = typename ShearStressSamplerBase<D>::View;
  explicit ShearStressSampler(std::shared_ptr<ShearStress> sums) : sums_(std::move(sums)) {}

  std::string name() const override { return "sample_srd_stress"; }
  bool reads_device_state(const World& world) const override { return !device_.ready(world); }
  // The step's sums are the ranks' totals; its own pass is totalled likewise.
  bool observes_by_rank() const override { return true; }

  void run_on(View view) override {
    const auto& cells = view.template read<SrdCells<D>>();
    // The layers across y: the box's (a rank's grid may be a slab along y).
    const auto slabs = static_cast<std::size_t>(cells.length[1]);
    if (const auto* device = device_.ready(view)) {
      const auto& rows = device_.layers(*device);
      const double m0 = cells.particle_mass;
      std::vector<double> slab_vx(slabs), slab_count(slabs);
      double n = 0.0;
      for (std::size_t k = 0; k < slabs; ++k) {
        slab_count[k] = rows[k * (3 + D)];
        slab_vx[k] = rows[k * (3 + D) + 1];
        n += slab_count[k];
      }
      sums_->add(m0 * device->stress[0] / n, m0 * device->stress[1] / n, m0 * device->stress[2] / n, m0,
                 device->transfer, slab_vx, slab_count);
      return;
    }
    // Particles of one mass (no Mass column): from the next step on, the device step sums.
    if (!view.template has<Mass>()) device_.ask(view, {1, 0, static_cast<int>(slabs)}, true);
    const auto& x = view.template read<Position<D>>();
    const auto& v = view.template read<Velocity<D>>();
    const double* mass = view.template has<Mass>() ? view.template read<Mass>().data() : nullptr;
    const double m0 = cells.particle_mass;
    const std::size_t n = view.size();
    const auto m = [&](std::size_t i) { return mass ? mass[i] : m0; };
    const double half = 0.5 * cells.length[1];
    std::vector<double> slab_vx(slabs, 0.0), slab_count(slabs, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const auto j = std::min(slabs - 1, static_cast<std::size_t>(x[i][1]));
      slab_vx[j] += v[i][0];
      slab_count[j] += 1.0;
    }
    enum { vxvy, vy_y, vy2, masses, transfer, particles, layers };
    std::vector<double> sums{
        deterministic_sum(n, [&](std::size_t i) { return m(i) * v[i][0] * v[i][1]; }),
        deterministic_sum(n, [&](std::size_t i) { return m(i) * v[i][1] * (x[i][1] - half); }),
        deterministic_sum(n, [&](std::size_t i) { return m(i) * v[i][1] * v[i][1]; }),
        deterministic_sum(n, m),
        deterministic_sum(cells.cell_count(), [&](std::size_t c) { return cells.owns(c) ? cells.transfer[c] : 0.0; }),
        static_cast<double>(n)};
    sums.insert(sums.end(), slab_vx.begin(), slab_vx.end());
    sums.insert(sums.end(), slab_count.begin(), slab_count.end());
    sums = view.part().total(sums);
    const double total = sums[particles];
    const auto layer = sums.begin() + layers;
    const auto slab = static_cast<std::ptrdiff_t>(slabs);
    sums_->add(sums[vxvy] / total, sums[vy_y] / total, sums[vy2] / total, sums[masses] / total, sums[transfer],
               std::vector<double>(layer, layer + slab), std::vector<double>(layer + slab, layer + 2 * slab));
  }

 private:
  std::shared_ptr<ShearStress> sums_;
  StepSumsRequest<D> device_;
};

template <int D>
class ShearViscosityObserver : public SystemOf<Reads<Velocity<D>>, Writes<ShearStress>> {
 public:
  using View = typename SystemOf<Reads<Velocity<D>>, Writes<ShearStress>>::View;
  explicit ShearViscosityObserver(std::shared_ptr<ShearStress> sums) : sums_(std::move(sums)) {}

  std::string name() const override { return "observe_srd_viscosity"; }
  bool observes_by_rank() const override { return true; }  // the sums are the same on every rank
  Access access() const override {
    return View::access()
        .writes_observable("shear_rate_measured", unit::rate)
        .writes_observable("viscosity_kinetic", unit::diffusivity)
        .writes_observable("viscosity_collisional", unit::diffusivity);
  }

  void run_on(View view) override {
    if (sums_->samples() == 0) return;
    auto& store = view.observables();
    const double rate = sums_->measured_shear_rate();
    const auto nu = sums_->viscosities(rate, view.part().total(static_cast<double>(view.size())));
    store.set("shear_rate_measured", rate);
    store.set("viscosity_kinetic", nu.kinetic);
    store.set("viscosity_collisional", nu.collisional);
  }

 private:
  std::shared_ptr<ShearStress> sums_;
};

}  // namespace granflow::srd
