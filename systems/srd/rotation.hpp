#pragma once
// The SRD collision: in every cell the thermal velocities v - V are rotated
// by alpha (2D: +-alpha at random; 3D: about a random axis), V kept, so
// momentum is conserved in every cell and, with restitution 1, energy too
// (Malevanets & Kapral 1999). Granular SRD scales the rotated thermal part by
// the cell's effective restitution eps_eff = 1 - (1 - eps^2) sigma^2 rho
// sqrt(theta) dt, clamped at 0, which makes the cooling rate of a cell
// proportional to rho theta^{3/2} as for inelastic hard spheres. Each cell's
// random numbers are keyed by (seed, step, cell).

#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <numbers>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/rng.hpp"
#include "engine/stream_ids.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_rotation_description{
    "srd_rotation", "stochastic rotation of each cell's thermal velocities, with the granular effective restitution"};

struct RotationParameters {
  double angle_degrees = 90.0;
  double restitution = 1.0;  // 1: standard SRD
  double diameter = 0.0;     // sigma of the effective restitution, in cell sizes
  double dt = 1.0;
  Dissipation rule = Dissipation::rotated_plane;
  // Sum each cell's collisional momentum transfer (for the shear stress).
  bool record_transfer = false;
};

// What every cell's rotation shares: the angle's cosine and sine (computed
// once, not per cell and step) and the dissipation rule.
template <int D>
CellRotation<D> rotation_base(const RotationParameters& p) {
  CellRotation<D> r;
  const double alpha = p.angle_degrees * std::numbers::pi / 180.0;
  r.cos_alpha = std::cos(alpha);
  r.sin_alpha = std::sin(alpha);
  r.rule = p.rule;
  return r;
}

// The rotation of cell `c` at `step`: its random sign (2D) or axis (3D), and
// the dissipation axis, before the granular factor is set.
template <int D>
CellRotation<D> cell_rotation(const CellRotation<D>& base, std::uint64_t seed, std::uint64_t step, std::uint64_t c) {
  CellRotation<D> r = base;
  Philox random(stream::srd_rotation, seed, step, c);
  if constexpr (D == 2) {
    if (random.uniform() >= 0.5) r.sin_alpha = -r.sin_alpha;
  } else {
    const double u1 = random.uniform(), u2 = random.uniform();
    unit_vector<3>(u1, u2, r.axis);
  }
  if (r.rule == Dissipation::random_axis) {
    const double u1 = random.uniform(), u2 = random.uniform();
    unit_vector<D>(u1, u2, r.direction);
  }
  return r;
}

template <int D>
class SrdRotation : public System {
 public:
  SrdRotation(RotationParameters parameters, std::uint64_t seed)
      : p_(parameters), base_(rotation_base<D>(parameters)), seed_(seed) {}

  std::string name() const override { return "srd_rotation"; }
  Access access() const override {
    return Access{}.reads<Clock, Position<D>>().template writes<Velocity<D>, SrdCells<D>>();
  }

  void run(World& world) override {
    auto& cells = world.resource<SrdCells<D>>();
    const auto step = static_cast<std::uint64_t>(world.resource<Clock>().step);
    auto& velocity = world.component<Velocity<D>>();
    const auto& position = world.component<Position<D>>();
    const double* mass = world.has_component<Mass>() ? world.component<Mass>().data() : nullptr;
    const double m0 = cells.particle_mass;
    const bool granular = p_.restitution < 1.0 && p_.diameter > 0.0;
    std::atomic<std::uint64_t> clamped{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cell_count(), 256), [&](const auto& range) {
      std::uint64_t clamped_here = 0;
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        const std::uint32_t begin = cells.start[c], end = cells.start[c + 1];
        cells.transfer[c] = 0.0;
        if (end - begin < 2) continue;  // one particle has no thermal velocity
        CellRotation<D> r = cell_rotation<D>(base_, seed_, step, c);
        if (granular) {
          bool below_zero = false;
          r.eps = effective_restitution(p_.restitution, p_.diameter, static_cast<double>(end - begin), cells.theta[c],
                                        p_.dt, below_zero);
          clamped_here += below_zero;
        }
        const Vec<D> mean = cells.velocity[c];
        double transfer = 0.0;
        for (std::uint32_t k = begin; k < end; ++k) {
          const std::uint32_t i = cells.order[k];
          const double image = image_velocity_x<D>(position[i].data(), cells.shift.data(), cells.length.data(), cells.shear);
          Vec<D> u = velocity[i] - mean;
          u[0] += image;
          r.apply(u.data());
          Vec<D> after = mean + u;
          after[0] -= image;
          if (D >= 2 && p_.record_transfer) {
            const double y = position[i][1] + cells.shift[1];
            transfer += (mass ? mass[i] : m0) * (after[0] - velocity[i][0]) * (y - std::floor(y) - 0.5);
          }
          velocity[i] = after;
        }
        cells.transfer[c] = transfer;
      }
      clamped += clamped_here;
    });
    cells.clamped_cells = clamped.load();
    total_clamped_ += cells.clamped_cells;
    if (cells.clamped_cells > 0 && !warned_) {
      warned_ = true;
      spdlog::warn("step {}: eps_eff <= 0 in {} cells (clamped to 0: those cells lose all their thermal energy); "
                   "lower srd.diameter, srd.time_step or the temperature to stay in the model's range",
                   step, cells.clamped_cells);
    }
  }

  // Cells clamped at eps_eff = 0 so far, summed over steps.
  std::uint64_t total_clamped() const { return total_clamped_; }

  const RotationParameters& parameters() const { return p_; }

 private:
  RotationParameters p_;
  CellRotation<D> base_;
  std::uint64_t seed_;
  std::uint64_t total_clamped_ = 0;
  bool warned_ = false;
};

}  // namespace granflow::srd
