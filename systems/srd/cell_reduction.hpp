#pragma once
// Per SRD cell: its mass, mean velocity V (mass-weighted, in the frame of
// the cell: across a shear plane, of the image it lies in) and temperature
// theta = sum m |v - V|^2 / (D n), in two passes over the cell's particles
// (the second about V, so no large sums cancel). Cells are independent and
// summed in a fixed order: the result does not depend on the thread count.

#include <tbb/parallel_for.h>

#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_cell_reduction_description{
    "srd_cell_reduction", "mass, mean velocity and temperature of every SRD cell (parallel over cells)"};

template <int D>
class SrdCellReduction : public System {
 public:
  std::string name() const override { return "srd_cell_reduction"; }
  Access access() const override { return Access{}.reads<Position<D>, Velocity<D>>().template writes<SrdCells<D>>(); }

  void run(World& world) override { reduce(world, world.resource<SrdCells<D>>()); }

  static void reduce(const World& world, SrdCells<D>& cells) {
    const auto& velocity = world.component<Velocity<D>>();
    const auto& position = world.component<Position<D>>();
    // Velocities as the cell sees them (Lees-Edwards images, srd_kernels.hpp).
    const auto seen = [&](std::uint32_t i) {
      Vec<D> v = velocity[i];
      v[0] += image_velocity_x<D>(position[i].data(), cells.shift.data(), cells.length.data(), cells.shear);
      return v;
    };
    const double* mass = world.has_component<Mass>() ? world.component<Mass>().data() : nullptr;
    const double m0 = cells.particle_mass;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cell_count(), 256), [&](const auto& range) {
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        const std::uint32_t begin = cells.start[c], end = cells.start[c + 1];
        double total = 0.0;
        Vec<D> momentum = Vec<D>::Zero();
        for (std::uint32_t k = begin; k < end; ++k) {
          const std::uint32_t i = cells.order[k];
          const double m = mass ? mass[i] : m0;
          total += m;
          momentum += m * seen(i);
        }
        const Vec<D> mean = total > 0.0 ? Vec<D>(momentum / total) : Vec<D>::Zero();
        double thermal = 0.0;
        for (std::uint32_t k = begin; k < end; ++k) {
          const std::uint32_t i = cells.order[k];
          thermal += (mass ? mass[i] : m0) * (seen(i) - mean).squaredNorm();
        }
        cells.mass[c] = total;
        cells.velocity[c] = mean;
        cells.theta[c] = end > begin ? thermal / (D * static_cast<double>(end - begin)) : 0.0;
      }
    });
  }
};

}  // namespace granflow::srd
