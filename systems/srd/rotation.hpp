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

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "components/clock.hpp"
#include "components/velocity.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
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

// Said once per run, at the first step with cells whose effective
// restitution fell below zero (over MPI ranks, all ranks' cells of that
// step: SrdDomainStep::report_clamping).
inline void warn_clamped_cells(std::int64_t step, std::uint64_t cells) {
  spdlog::warn("step {}: eps_eff <= 0 in {} cells (clamped to 0: those cells lose all their thermal energy); lower "
               "srd.diameter, srd.time_step or the temperature to stay in the model's range",
               step, cells);
}

inline GranularParameters granular_parameters(const RotationParameters& p) {
  return {p.restitution < 1.0 && p.diameter > 0.0, p.restitution, p.diameter, p.dt};
}

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

template <int D>
class SrdRotation : public SystemOf<Reads<Clock>, Writes<Velocity<D>, SrdCells<D>>> {
 public:
  using View = typename SystemOf<Reads<Clock>, Writes<Velocity<D>, SrdCells<D>>>::View;
  SrdRotation(RotationParameters parameters, std::uint64_t seed)
      : p_(parameters), base_(rotation_base<D>(parameters)), seed_(seed) {}

  std::string name() const override { return "srd_rotation"; }

  void run_on(View view) override {
    auto& cells = view.template write<SrdCells<D>>();
    const auto step = static_cast<std::uint64_t>(view.template read<Clock>().step);
    const GranularParameters granular = granular_parameters(p_);
    const bool transfer = p_.record_transfer && D >= 2 && cells.record_moments;
    const std::size_t cell_count = cells.cell_count();
    collisions_.resize(cell_count);
    // Each cell's operator, from its random numbers and (granular) its density and temperature.
    std::atomic<std::uint64_t> clamped{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cell_count, 256), [&](const auto& range) {
      std::uint64_t clamped_here = 0;
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        CellCollision& collision = collisions_[c];
        for (int a = 0; a < D; ++a) collision.mean[a] = cells.velocity[c][a];
        const double members = cells.count[c] + (cells.ghosts.empty() ? 0.0 : cells.ghosts[c]);
        bool below_zero = false;
        cell_collision_matrix<D>(base_, granular, seed_, step, cells.cell_key(c), members, cells.theta[c], collision.matrix, below_zero);
        // Counted where it is owned: over ranks a straddling cell is rotated on both sides.
        if (below_zero && cells.owns(c)) ++clamped_here;
        cells.transfer[c] = transfer && members >= 2 ? collisional_transfer<D>(collision.matrix, cells.moment[c].data()) : 0.0;
      }
      clamped += clamped_here;
    });
    // Then every particle, independently.
    double* v = view.template write<Velocity<D>>().data()->data();
    const std::uint32_t* cell = cells.cell.data();
    const std::int8_t* image = cells.image.empty() ? nullptr : cells.image.data();
    const double image_speed = cells.shear.velocity;
    const CellCollision* collisions = collisions_.data();
    if (!cells.record_energy) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, view.size(), 4096), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          if (i + prefetch_distance < range.end()) prefetch(collisions + cell[i + prefetch_distance]);
          const CellCollision& collision = collisions[cell[i]];
          collide_particle<D>(v + D * i, collision.matrix, collision.mean, image ? -image[i] * image_speed : 0.0);
        }
      });
    } else {
      collide_and_account(view.size(), cells, v, image, image_speed);
    }
    cells.clamped_cells = clamped.load();
    total_clamped_ += cells.clamped_cells;
    if (cells.clamped_cells > 0 && first_clamped_step_ < 0) {
      first_clamped_step_ = static_cast<std::int64_t>(step);
      first_clamped_cells_ = cells.clamped_cells;
      if (!quiet_) warn_clamped_cells(first_clamped_step_, first_clamped_cells_);
    }
  }

  // Cells clamped at eps_eff = 0 so far, summed over steps.
  std::uint64_t total_clamped() const { return total_clamped_; }
  // The first step that clamped cells (-1: none yet) and how many it did.
  std::int64_t first_clamped_step() const { return first_clamped_step_; }
  std::uint64_t first_clamped_cells() const { return first_clamped_cells_; }
  // Leaves the warning to the caller (a step over ranks says it for all).
  void quiet() { quiet_ = true; }

  const RotationParameters& parameters() const { return p_; }

 private:
  // The particle pass with the energy bookkeeping: each particle's change of
  // kinetic energy, summed per fixed chunk of particles (the same sums on
  // any thread count), apart for cells with and without ghost particles.
  void collide_and_account(std::size_t n, SrdCells<D>& cells, double* v, const std::int8_t* image, double image_speed) {
    constexpr std::size_t chunk = 4096;
    const std::size_t chunks = (n + chunk - 1) / chunk;
    chunk_energy_.assign(2 * chunks, 0.0);
    const std::uint32_t* cell = cells.cell.data();
    const std::uint32_t* ghosts = cells.ghosts.empty() ? nullptr : cells.ghosts.data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        double plain = 0.0, ghosted = 0.0;
        const std::size_t end = std::min(n, (k + 1) * chunk);
        for (std::size_t i = k * chunk; i != end; ++i) {
          double* vi = v + D * i;
          double before = 0.0, after = 0.0;
          for (int a = 0; a < D; ++a) before += vi[a] * vi[a];
          const CellCollision& collision = collisions_[cell[i]];
          collide_particle<D>(vi, collision.matrix, collision.mean, image ? -image[i] * image_speed : 0.0);
          for (int a = 0; a < D; ++a) after += vi[a] * vi[a];
          if (cells.copies && cells.copies[i]) continue;
          (ghosts && ghosts[cell[i]] > 0 ? ghosted : plain) += 0.5 * (after - before);
        }
        chunk_energy_[2 * k] = plain;
        chunk_energy_[2 * k + 1] = ghosted;
      }
    });
    double plain = 0.0, ghosted = 0.0;
    for (std::size_t k = 0; k < chunks; ++k) {
      plain += chunk_energy_[2 * k];
      ghosted += chunk_energy_[2 * k + 1];
    }
    cells.step_collision_energy = cells.particle_mass * plain;
    cells.step_ghost_cell_energy = cells.particle_mass * ghosted;
  }

  RotationParameters p_;
  CellRotation<D> base_;
  std::uint64_t seed_;
  // A cell's operator and mean velocity together: one record per particle's lookup.
  struct CellCollision {
    double matrix[D * D];
    double mean[D];
  };
  std::vector<CellCollision> collisions_;  // per cell, this step's
  std::vector<double> chunk_energy_;
  std::uint64_t total_clamped_ = 0;
  std::int64_t first_clamped_step_ = -1;
  std::uint64_t first_clamped_cells_ = 0;
  bool quiet_ = false;
};

}  // namespace granflow::srd
