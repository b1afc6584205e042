#pragma once
// Per SRD cell: its particle count, mass, mean velocity V (mass-weighted, in
// the frame of the cell: across a shear plane, of the image it lies in) and
// temperature theta = sum m |v - V|^2 / (D n). One pass over the particles:
// the sums are taken about the velocity of the cell's first particle, so the
// variance does not come from the difference of two large sums however fast
// the cell moves (the shifted-data form of the two-pass formula).
//
// Parallel over ranges of cells: each task reads the blocks of particles
// that reach into its cells and adds, cell by cell, their particles in
// storage order, so the result does not depend on the thread count.

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_cell_reduction_description{
    "srd_cell_reduction", "count, mass, mean velocity and temperature of every SRD cell (parallel over cell ranges)"};

template <int D>
class SrdCellReduction : public SystemOf<Reads<Clock, Position<D>, Velocity<D>, Mass>, Writes<SrdCells<D>>> {
 public:
  using View = typename SystemOf<Reads<Clock, Position<D>, Velocity<D>, Mass>, Writes<SrdCells<D>>>::View;
  using ParticleView = granflow::View<Reads<Clock, Position<D>, Velocity<D>, Mass>, Writes<>>;
  std::string name() const override { return "srd_cell_reduction"; }

  void run_on(View view) override { reduce(view, view.template write<SrdCells<D>>()); }

  // Needs SrdCellBinning::assign's cells and blocks of the current positions.
  static void reduce(const ParticleView& view, SrdCells<D>& cells) {
    const double time = view.template read<Clock>().time;
    const auto step = static_cast<std::uint64_t>(view.template read<Clock>().step);
    CutLayer cuts[6];
    const int cut_count = find_cut_layers(cells.walls.data(), static_cast<int>(cells.walls.size()), cells.cells.data(),
                                          cells.shift.data(), cells.origin.data(), time, cuts);
    const Vec<D>* velocity = view.template read<Velocity<D>>().data();  // D doubles each, packed
    const double* x = view.template read<Position<D>>().data()->data();
    const double* mass = view.template has<Mass>() ? view.template read<Mass>().data() : nullptr;
    const double m0 = cells.particle_mass;
    const std::size_t n = view.size(), cell_count = cells.cell_count();
    const bool moments = cells.record_moments && D >= 2;
    if (moments) {
      cells.moment.resize(cell_count);
      cells.moment_mass.resize(cell_count);
    }
    const std::uint32_t* cell = cells.cell.data();
    const std::int8_t* image = cells.image.empty() ? nullptr : cells.image.data();
    const double image_speed = cells.shear.velocity;
    const BlockCells* blocks = cells.blocks.data();
    const std::size_t block_count = cells.blocks.size(), block = SrdCells<D>::block_size;
    const double y_shift = D >= 2 ? cells.shift[1] : 0.0;
    // Raw columns, so that the compiler knows the sums do not move them.
    std::uint32_t* count = cells.count.data();
    CellSums<D>* sums = cells.sums.data();
    double* moment = moments ? cells.moment.data()->data() : nullptr;
    double* moment_mass = moments ? cells.moment_mass.data() : nullptr;
    const double* v = velocity->data();
    // Few, wide ranges: a block is reread by every range its cells reach
    // into, and between reorderings the particles spread over several
    // planes of cells.
    const auto threads = static_cast<std::size_t>(tbb::this_task_arena::max_concurrency());
    const std::size_t grain = std::max<std::size_t>(1024, cell_count / (2 * threads));
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, cell_count, grain),
        [&](const auto& range) {
          const auto begin = static_cast<std::uint32_t>(range.begin()), end = static_cast<std::uint32_t>(range.end());
          std::fill(count + begin, count + end, 0u);
          if (moments) {
            std::fill(moment + D * begin, moment + D * end, 0.0);
            std::fill(moment_mass + begin, moment_mass + end, 0.0);
          }
          for (std::size_t b = 0; b < block_count; ++b) {
            if (!blocks[b].meets(begin, end, static_cast<std::uint32_t>(cell_count))) continue;
            const std::size_t last = std::min(n, (b + 1) * block);
            for (std::size_t i = b * block; i < last; ++i) {
              const std::uint32_t c = cell[i];
              if (c < begin || c >= end) continue;
              double seen[D];
              for (int a = 0; a < D; ++a) seen[a] = v[D * i + a];
              if (image) seen[0] -= image[i] * image_speed;
              CellSums<D>& s = sums[c];
              if (count[c]++ == 0) start_sums<D>(s, seen);
              double w[D];
              const double m = mass ? mass[i] : m0;
              add_to_sums<D>(s, seen, m, w);
              if (moments) {
                const double y = x[D * i + 1] + y_shift;
                const double offset = moment_offset(m, y);
                for (int a = 0; a < D; ++a) moment[D * c + a] += offset * w[a];
                moment_mass[c] += offset;
              }
            }
          }
          if (!cells.walls.empty())
            for (std::uint32_t c = begin; c < end; ++c)
              cells.ghosts[c] = fill_cut_cell<D>(cells.sums[c], cells.count[c], c, cells.cell_key(c), cuts, cut_count, cells.walls.data(),
                                                 cells.cells.data(), cells.ghost_fill, time, cells.particle_mass,
                                                 cells.seed, step);
          for (std::uint32_t c = begin; c < end; ++c) {
            if (count[c] == 0) {
              cells.mass[c] = 0.0;
              cells.velocity[c] = Vec<D>::Zero();
              cells.theta[c] = 0.0;
              continue;
            }
            const double members = count[c] + (cells.ghosts.empty() ? 0.0 : cells.ghosts[c]);
            double drift[D];
            finish_sums<D>(sums[c], members, cells.velocity[c].data(), cells.theta[c], drift);
            cells.mass[c] = sums[c].mass;
            if (moments)
              for (int a = 0; a < D; ++a) moment[D * c + a] -= moment_mass[c] * drift[a];
          }
        },
        tbb::simple_partitioner{});
  }
};

}  // namespace granflow::srd
