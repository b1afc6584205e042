#pragma once
// Thermostat of sheared standard SRD: the global drift is removed, then the
// thermal velocities (each relative to its cell's mean velocity) of all
// particles are scaled by one factor so that the temperature is the target.
// One global factor, not one per cell: rescaling each cell to the target
// would set every cell's thermal energy and suppress the temperature
// fluctuations the fluid must have. Shear heating is removed as it arises.

#include <tbb/parallel_for.h>

#include <cmath>

#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_thermostat_description{
    "srd_thermostat", "global rescaling of the thermal velocities (relative to the cell means) to a target temperature"};

template <int D>
class SrdThermostat : public System {
 public:
  explicit SrdThermostat(double temperature) : temperature_(temperature) {}

  std::string name() const override { return "srd_thermostat"; }
  Access access() const override { return Access{}.reads<Position<D>>().template writes<Velocity<D>, SrdCells<D>>(); }

  void run(World& world) override {
    auto& cells = world.resource<SrdCells<D>>();
    auto& velocity = world.component<Velocity<D>>();
    const auto& position = world.component<Position<D>>();
    const auto image = [&](std::uint32_t i) {
      return image_velocity_x<D>(position[i].data(), cells.shift.data(), cells.length.data(), cells.shear);
    };
    const double* mass = world.has_component<Mass>() ? world.component<Mass>().data() : nullptr;
    const double m0 = cells.particle_mass;
    const std::size_t n = world.size();
    // Global drift (mass-weighted mean velocity), summed in a fixed order.
    Vec<D> momentum = Vec<D>::Zero();
    double total = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double m = mass ? mass[i] : m0;
      momentum += m * velocity[i];
      total += m;
    }
    const Vec<D> drift = momentum / total;
    // Thermal energy about the cell means (which the rotation left unchanged).
    double thermal = 0.0;
    std::size_t occupied = 0;
    for (std::size_t c = 0; c < cells.cell_count(); ++c) {
      if (cells.particles_in(c) == 0) continue;
      ++occupied;
      for (std::uint32_t k = cells.start[c]; k < cells.start[c + 1]; ++k) {
        const std::uint32_t i = cells.order[k];
        Vec<D> u = velocity[i] - cells.velocity[c];
        u[0] += image(i);
        thermal += (mass ? mass[i] : m0) * u.squaredNorm();
      }
    }
    // Each occupied cell's mean velocity takes D degrees of freedom.
    const double dof = static_cast<double>(D) * static_cast<double>(n - occupied);
    if (thermal <= 0.0 || dof <= 0.0) return;
    const double factor = std::sqrt(temperature_ * dof / thermal);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cell_count(), 256), [&](const auto& range) {
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        const Vec<D> mean = cells.velocity[c];
        for (std::uint32_t k = cells.start[c]; k < cells.start[c + 1]; ++k) {
          const std::uint32_t i = cells.order[k];
          Vec<D> u = velocity[i] - mean;
          u[0] += image(i);
          velocity[i] = mean - drift + factor * u;
          velocity[i][0] -= image(i);
        }
        cells.velocity[c] = mean - drift;
      }
    });
  }

 private:
  double temperature_;
};

}  // namespace granflow::srd
