#pragma once
// The thermodynamic state of an SRD fluid, from the particles and this
// step's cells:
//   temperature                sum m |v - V_cell|^2 / (D (N - occupied cells)): thermal, about the local flow
//   granular_temperature       sum m |v - <v>|^2 / (D N): about the global mean, the flow included
//   convective_kinetic_energy  (1/N) sum_cells M_cell |V_cell|^2
//   density_std                standard deviation of the particles per cell
//   mach_number                sqrt(convective_kinetic_energy / temperature): 1 where the two cross
//   mach_number_local          |V_cell| / sqrt(theta_cell / m), averaged over particles (cells of 2 or more)
//   sonine_a2, sonine_a3       Sonine coefficients of the distribution of v - <v>
// All sums run in a fixed order, so the values do not depend on the thread
// count; over ranks each rank sums its own part, totalled in rank order.

#include <cmath>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/global_motion.hpp"
#include "systems/srd/srd_cell_kernels.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription observe_srd_state_description{
    "observe_srd_state", "temperature, granular temperature, convective energy, density fluctuations, Mach number, Sonine a2 and a3"};

// The Sonine coefficient a2 of the homogeneous cooling state of inelastic
// hard spheres (d = 3) or disks (d = 2) of restitution e, in the first
// Sonine approximation (van Noije & Ernst 1998; Brilliantov & Poeschel 2004).
inline double homogeneous_cooling_a2(double e, int d) {
  return 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e) / (9.0 + 24.0 * d - e * (41.0 - 8.0 * d) + 30.0 * e * e * (1.0 - e));
}

template <int D>
class SrdStateObserver : public SystemOf<Reads<Clock, Velocity<D>, Mass, SrdCells<D>>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Clock, Velocity<D>, Mass, SrdCells<D>>, Writes<>>::View;
  // Granular SRD also gets eps_eff at the mean density of the occupied cells
  // and the granular temperature, and the a2 of hard spheres of that restitution.
  explicit SrdStateObserver(const GranularParameters& granular = {}) : granular_(granular) {}
  std::string name() const override { return "observe_srd_state"; }
  Access access() const override {
    Access access = View::access();
    if (granular_.on)
      access.writes_observable("effective_restitution", unit::none).writes_observable("sonine_a2_hcs", unit::none);
    return access
        .writes_observable("temperature", unit::energy)
        .writes_observable("granular_temperature", unit::energy)
        .writes_observable("convective_kinetic_energy", unit::energy)
        .writes_observable("density_std", unit::none)
        .writes_observable("mach_number", unit::none)
        .writes_observable("mach_number_local", unit::none)
        .writes_observable("sonine_a2", unit::none)
        .writes_observable("sonine_a3", unit::none);
  }

  // Each rank sums over its own particles and cells (SrdCells::owns); the
  // sums are totalled over the ranks.
  bool observes_by_rank() const override { return true; }

  void run_on(View view) override {
    const auto& cells = view.template read<SrdCells<D>>();
    const auto& velocity = view.template read<Velocity<D>>();
    const double* mass = view.template has<Mass>() ? view.template read<Mass>().data() : nullptr;
    const double m0 = cells.particle_mass;
    const std::size_t n = view.size();
    const auto m = [&](std::size_t i) { return mass ? mass[i] : m0; };
    const ObservedPart& part = view.part();
    auto& store = view.observables();

    const std::size_t c_count = cells.cell_count();
    const std::uint32_t* cell = cells.cell.data();
    // Between walls, only the cells wholly inside them (this step's grid):
    // the others are cut, or beyond the walls.
    const double time = view.template read<Clock>().time;
    const auto counted = [&](std::size_t c) {
      return cells.owns(c) && (cells.walls.empty() || cells.inside_walls(c, time));
    };
    const auto over_cells = [&](auto&& term) {
      return deterministic_sum(c_count, [&](std::size_t c) { return cells.owns(c) ? term(c) : 0.0; });
    };
    enum { particles, occupied, thermal, convective, counted_cells, counted_particles };
    const std::vector<double> sums = part.total({
        static_cast<double>(n),
        over_cells([&](std::size_t c) { return cells.particles_in(c) > 0 ? 1.0 : 0.0; }),
        deterministic_sum(n,
                          [&](std::size_t i) {
                            Vec<D> u = velocity[i] - cells.velocity[cell[i]];
                            u[0] += cells.image_velocity(i);
                            return m(i) * u.squaredNorm();
                          }),
        over_cells([&](std::size_t c) { return cells.mass[c] * cells.velocity[c].squaredNorm(); }),
        deterministic_sum(c_count, [&](std::size_t c) { return counted(c) ? 1.0 : 0.0; }),
        deterministic_sum(c_count, [&](std::size_t c) { return counted(c) ? cells.particles_in(c) : 0.0; }),
    });
    const double total = sums[particles];
    const double mean_count = sums[counted_particles] / std::max(sums[counted_cells], 1.0);
    const GlobalMotion<D> global = observed_motion<D>(view, m0);
    const Vec<D>& mean = global.mean;
    const auto speed2 = [&](std::size_t i) { return (velocity[i] - mean).squaredNorm(); };
    // The local Mach number, weighted by the particles of cells of 2 or more.
    double weighted = 0.0, weights = 0.0;
    for (std::size_t c = 0; c < c_count; ++c) {
      const double k = cells.particles_in(c);
      if (!cells.owns(c) || k < 2 || cells.theta[c] <= 0) continue;
      weighted += k * cells.velocity[c].norm() / std::sqrt(cells.theta[c] * k / cells.mass[c]);
      weights += k;
    }
    enum { count_squares, moment2, moment4, moment6, mach_weighted, mach_weights };
    const std::vector<double> spread = part.total({
        deterministic_sum(c_count,
                          [&](std::size_t c) {
                            if (!counted(c)) return 0.0;
                            const double d = cells.particles_in(c) - mean_count;
                            return d * d;
                          }),
        deterministic_sum(n, speed2),
        deterministic_sum(n, [&](std::size_t i) { return speed2(i) * speed2(i); }),
        deterministic_sum(n, [&](std::size_t i) { return speed2(i) * speed2(i) * speed2(i); }),
        weighted,
        weights,
    });
    const double count_variance = spread[count_squares] / std::max(sums[counted_cells], 1.0);
    const double c2 = spread[moment2] / total, c4 = spread[moment4] / total, c6 = spread[moment6] / total;
    const double granular = global.granular_temperature;
    const double dof = D * (total - sums[occupied]);
    const double temperature = dof > 0 ? sums[thermal] / dof : 0.0;
    const double kinetic_convective = sums[convective] / total;
    const double d = D;
    const double a2 = c2 > 0 ? d / (d + 2.0) * c4 / (c2 * c2) - 1.0 : 0.0;
    const double a3 = c2 > 0 ? 1.0 + 3.0 * a2 - c6 / (c2 * c2 * c2) * d * d / ((d + 2.0) * (d + 4.0)) : 0.0;
    store.set("temperature", temperature);
    store.set("granular_temperature", granular);
    store.set("convective_kinetic_energy", kinetic_convective);
    store.set("density_std", std::sqrt(count_variance));
    store.set("mach_number", temperature > 0 ? std::sqrt(kinetic_convective / temperature) : 0.0);
    store.set("mach_number_local", spread[mach_weights] > 0 ? spread[mach_weighted] / spread[mach_weights] : 0.0);
    store.set("sonine_a2", a2);
    store.set("sonine_a3", a3);
    if (granular_.on) {
      bool clamped = false;
      const double density = sums[occupied] > 0 ? total / sums[occupied] : 0.0;
      // theta in energy units, as the cells hand it to the collision (cell_reduction.hpp).
      const double eps = effective_restitution(granular_.restitution, granular_.diameter, density, granular,
                                               granular_.dt, clamped);
      store.set("effective_restitution", eps);
      store.set("sonine_a2_hcs", homogeneous_cooling_a2(eps, D));
    }
  }

 private:
  GranularParameters granular_;
};

}  // namespace granflow::srd
