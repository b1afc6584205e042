#pragma once
// Thermostat of sheared standard SRD: the global drift is removed, then the
// thermal velocities (each relative to its cell's mean velocity) of all
// particles are scaled by one factor so that the temperature is the target.
// One global factor, not one per cell: rescaling each cell to the target
// would set every cell's thermal energy and suppress the temperature
// fluctuations the fluid must have. Shear heating is removed as it arises.

#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/srd_cell_kernels.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_thermostat_description{
    "srd_thermostat", "global rescaling of the thermal velocities (relative to the cell means) to a target temperature"};

template <int D>
class SrdThermostat : public SystemOf<Reads<Mass>, Writes<Velocity<D>, SrdCells<D>>> {
 public:
  using View = typename SystemOf<Reads<Mass>, Writes<Velocity<D>, SrdCells<D>>>::View;
  // remove_drift: take the global mean velocity out first (a periodic box;
  // between walls the flow is the physics).
  explicit SrdThermostat(double temperature, bool remove_drift = true)
      : temperature_(temperature), remove_drift_(remove_drift) {}

  std::string name() const override { return "srd_thermostat"; }

  void run_on(View view) override {
    const double* mass = view.template has<Mass>() ? view.template read<Mass>().data() : nullptr;
    const auto every = [](std::size_t) { return true; };
    rescale(view.template write<Velocity<D>>().data(), mass, view.size(), view.template write<SrdCells<D>>(),
            temperature_, remove_drift_, every, every, [](std::vector<double> sums) { return sums; });
  }

  // The rescaling of `n` particles in `cells`, of which the ones `counted`
  // (a particle's index) are this grid's own and the cells `owned` (a cell's
  // index) too: the global sums are those of the owned ones, added over every
  // part of the system by `add_across` (a vector of sums in, their totals
  // out), so that ranks holding copies of each other's particles scale all
  // by one factor.
  template <class Counted, class Owned, class AddAcross>
  static void rescale(Vec<D>* velocity, const double* mass, std::size_t n, SrdCells<D>& cells, double temperature,
                      bool remove_drift, Counted counted, Owned owned, AddAcross add_across) {
    const double m0 = cells.particle_mass;
    const auto m = [&](std::size_t i) { return counted(i) ? (mass ? mass[i] : m0) : 0.0; };
    const std::uint32_t* cell = cells.cell.data();
    // A particle's velocity relative to its cell's mean, as the cell sees it.
    const auto thermal_velocity = [&](std::size_t i) {
      Vec<D> u = velocity[i] - cells.velocity[cell[i]];
      u[0] += cells.image_velocity(i);
      return u;
    };
    // Summed in a fixed order: mass, momentum, the thermal energy about the
    // cell means (which the rotation left unchanged), occupied cells, particles.
    std::vector<double> sums(D + 4, 0.0);
    sums[0] = deterministic_sum(n, m);
    if (remove_drift)
      for (int a = 0; a < D; ++a) sums[1 + a] = deterministic_sum(n, [&](std::size_t i) { return m(i) * velocity[i][a]; });
    sums[D + 1] = deterministic_sum(n, [&](std::size_t i) { return m(i) * thermal_velocity(i).squaredNorm(); });
    sums[D + 2] = deterministic_sum(cells.cell_count(), [&](std::size_t c) { return cells.count[c] > 0 && owned(c) ? 1.0 : 0.0; });
    sums[D + 3] = deterministic_sum(n, [&](std::size_t i) { return counted(i) ? 1.0 : 0.0; });
    sums = add_across(std::move(sums));
    Vec<D> drift = Vec<D>::Zero();
    if (remove_drift)
      for (int a = 0; a < D; ++a) drift[a] = sums[1 + a] / sums[0];
    const double thermal = sums[D + 1];
    // Each occupied cell's mean velocity takes D degrees of freedom.
    const double dof = D * (sums[D + 3] - sums[D + 2]);
    if (thermal <= 0.0 || dof <= 0.0) return;
    const double factor = std::sqrt(temperature * dof / thermal);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        thermostat_velocity<D>(velocity[i].data(), cells.velocity[cell[i]].data(), drift.data(), factor,
                               cells.image_velocity(i));
      }
    });
    tbb::parallel_for(std::size_t{0}, cells.cell_count(), [&](std::size_t c) { cells.velocity[c] -= drift; });
  }

 private:
  double temperature_;
  bool remove_drift_;
};

}  // namespace granflow::srd
