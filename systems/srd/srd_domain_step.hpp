#pragma once
// The SRD step of one periodic system spread over the ranks of an MPI job
// (`mpirun -np K granflow run`): each rank owns the particles of one slab of
// cells along the last axis (slab_domain.hpp) and steps them with the same
// systems one rank runs (streaming, grid shift, binning, reduction,
// rotation), on a grid of its slab and two layers either side. Per step:
//
//  - streaming, then the particles that left the slab go to the rank that
//    owns them now (a particle fast enough to cross a whole slab is passed
//    on in further rounds);
//  - the shifted cells that straddle a slab boundary hold particles of two
//    ranks: each rank receives copies of its neighbours' particles within
//    one cell of its boundaries (ghosts), so that it reduces and rotates
//    those cells over all their particles, as one rank would;
//  - each cell's random rotation is keyed by its cell of the whole grid
//    (SrdCells::cell_key), so every rank draws one rank's numbers.
//
// What stays the same as on one rank and what does not: the random numbers,
// the cells and the particles in each are the same; a straddling cell's
// sums are taken over the same particles in another order, so the results
// agree to round-off (measured in docs/srd.md), not bit for bit. On the same
// number of ranks a run is bit for bit the same on any thread count, and
// resumes bit for bit.
//
// Observers and checkpoints read the World, which here is the whole system:
// synchronise_host gathers every rank's particles into it, in rank order, on
// every rank (so observers decide the same everywhere), with this step's
// cells as the reduction left them before the rotation, as on one rank. A resumed run scatters that World back by slab,
// which gives each rank its particles in the order it held them.

#include <spdlog/spdlog.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "components/clock.hpp"
#include "components/image_count.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/communicator.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/srd/cell_binning.hpp"
#include "systems/srd/cell_reduction.hpp"
#include "systems/srd/grid_shift.hpp"
#include "systems/srd/rotation.hpp"
#include "systems/srd/slab_domain.hpp"
#include "systems/srd/srd_cells.hpp"
#include "systems/srd/streaming.hpp"

namespace granflow::srd {

inline const SystemDescription srd_domain_step_description{
    "srd_domain_step",
    "the SRD step over MPI ranks: slabs of cells, particles migrated and ghost layers exchanged every step"};

// Marks a rank's copies of its neighbours' particles for the current step.
struct DomainGhost : Column<std::uint8_t> {
  static constexpr const char* key = "domain_ghost";
};

template <int D>
using SrdDomainStepBase = SystemOf<Reads<>, Writes<EveryColumn, Clock, SrdCells<D>, RunControl>>;

template <int D>
class SrdDomainStep : public SrdDomainStepBase<D> {
 public:
  using View = typename SrdDomainStepBase<D>::View;

  SrdDomainStep(const Communicator& ranks, double dt, const RotationParameters& rotation, std::uint64_t seed,
                bool grid_shift, std::uint64_t reorder_interval, const SrdCells<D>& whole)
      : ranks_(ranks),
        slab_(ranks.rank(), ranks.size(), whole.cells[D - 1]),
        length_(whole.length[D - 1]),
        streaming_(dt, 0.0),
        shift_(seed, grid_shift),
        binning_(reorder_interval),
        rotation_(rotation, seed) {
    local_.emplace_resource<Clock>();
    local_.emplace_resource<RunControl>();
    std::array<std::int32_t, D> dims = whole.cells;
    const auto low = slab_.low(), width = slab_.high() - slab_.low();
    dims[D - 1] = static_cast<std::int32_t>(width + 4);
    auto& cells = local_.emplace_resource<SrdCells<D>>(dims, 0);
    cells.length = whole.length;
    cells.origin[D - 1] = static_cast<double>(low - 2);
    cells.bounded |= 1u << (D - 1);  // its own grid ends at the halo: no wrap there
    cells.particle_mass = whole.particle_mass;
    cells.ghost_fill = whole.ghost_fill;
    cells.seed = whole.seed;
    std::uint64_t stride = 1;
    for (int a = 0; a + 1 < D; ++a) stride *= static_cast<std::uint64_t>(whole.cells[a]);
    const auto along = static_cast<std::int64_t>(whole.cells[D - 1]);
    cells.key_period = stride * static_cast<std::uint64_t>(along);
    cells.key_offset = static_cast<std::uint64_t>(((low - 2) % along + along) % along) * stride;
  }

  std::string name() const override { return "srd_domain_step"; }

  void run_on(View view) override {
    if (!scattered_) scatter(view);
    streaming_.run(local_);
    migrate();
    shift_.run(local_);
    add_ghosts();
    binning_.run(local_);
    SrdCellReduction<D>::reduce(local_, local_.resource<SrdCells<D>>());
    rotation_.run(local_);
    drop(local_.component<DomainGhost>().values, std::uint8_t{1});
    view.template write<Clock>() = local_.resource<Clock>();
    view.template write<SrdCells<D>>().shift = local_.resource<SrdCells<D>>().shift;
    ranks_.agree_on_interrupt();
    host_current_ = false;
  }

  // Every rank's particles into the whole World, on every rank, and the
  // whole grid's cells from them.
  void synchronise_host(World& whole) override {
    if (host_current_ || !scattered_) return;
    std::vector<double> mine;
    mine.reserve(local_.size() * width());
    for (std::size_t i = 0; i < local_.size(); ++i) pack(i, mine, 0.0);
    const std::vector<double> all = ranks_.gather_all(mine);
    const std::size_t n = all.size() / width();
    whole.resize(n);
    auto& x = whole.component<Position<D>>();
    auto& v = whole.component<Velocity<D>>();
    ParticleId* id = ids_ ? &whole.component<ParticleId>() : nullptr;
    ImageCount<D>* image = images_ ? &whole.component<ImageCount<D>>() : nullptr;
    for (std::size_t i = 0; i < n; ++i) unpack(all.data() + i * width(), x[i], v[i], id, image, i);
    auto& cells = whole.resource<SrdCells<D>>();
    SrdCellBinning<D>::assign(x, cells);
    gather_cells(cells);
    cells.clamped_cells =
        static_cast<std::uint64_t>(ranks_.sum(static_cast<std::int64_t>(local_.resource<SrdCells<D>>().clamped_cells)));
    host_current_ = true;
  }

 private:
  std::size_t width() const { return 2 * D + (ids_ ? 1 : 0) + (images_ ? D : 0); }

  // This step's cells (as the reduction left them, before the rotation) into
  // the whole grid. Each cell comes from the rank that owns its lower edge,
  // where it is whole: its particles above the slab are that rank's ghosts.
  void gather_cells(SrdCells<D>& whole) const {
    const auto& local = local_.resource<SrdCells<D>>();
    const double s = local.shift[D - 1], low = static_cast<double>(slab_.low()), high = static_cast<double>(slab_.high());
    std::size_t stride = 1;
    for (int a = 0; a + 1 < D; ++a) stride *= static_cast<std::size_t>(local.cells[a]);
    constexpr std::size_t record = 4 + D;
    std::vector<double> mine;
    for (std::int32_t k = 0; k < local.cells[D - 1]; ++k) {
      const double edge = local.origin[D - 1] + k - s;
      if (edge < low || edge >= high) continue;
      for (std::size_t c = k * stride; c < (k + 1) * stride; ++c) {
        mine.push_back(static_cast<double>(local.cell_key(c)));
        mine.push_back(local.count[c]);
        mine.push_back(local.mass[c]);
        mine.push_back(local.theta[c]);
        for (int a = 0; a < D; ++a) mine.push_back(local.velocity[c][a]);
      }
    }
    const std::vector<double> all = ranks_.gather_all(mine);
    for (std::size_t r = 0; r + record <= all.size(); r += record) {
      const auto c = static_cast<std::size_t>(all[r]);
      whole.count[c] = static_cast<std::uint32_t>(all[r + 1]);
      whole.mass[c] = all[r + 2];
      whole.theta[c] = all[r + 3];
      for (int a = 0; a < D; ++a) whole.velocity[c][a] = all[r + 4 + static_cast<std::size_t>(a)];
    }
  }

  // This rank's particles of the whole World (the initial state, or the one
  // a checkpoint restored), in the World's order.
  void scatter(View view) {
    const auto& x = view.template read<Position<D>>();
    const auto& v = view.template read<Velocity<D>>();
    ids_ = view.template has<ParticleId>();
    images_ = view.template has<ImageCount<D>>();
    local_.add_component<Position<D>>();
    local_.add_component<Velocity<D>>();
    local_.add_component<DomainGhost>();
    if (ids_) local_.add_component<ParticleId>();
    if (images_) local_.add_component<ImageCount<D>>();
    std::vector<double> mine;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (slab_.owner(x[i][D - 1]) != slab_.rank) continue;
      for (int a = 0; a < D; ++a) mine.push_back(x[i][a]);
      for (int a = 0; a < D; ++a) mine.push_back(v[i][a]);
      if (ids_) mine.push_back(view.template read<ParticleId>()[i]);
      if (images_)
        for (int a = 0; a < D; ++a) mine.push_back(view.template read<ImageCount<D>>()[i][a]);
    }
    append(mine, 0);
    local_.resource<Clock>() = view.template read<Clock>();
    scattered_ = true;
  }

  // Particle i's columns onto `out`, moved by `offset` along the slab axis
  // (into the frame of the rank across the periodic edge).
  void pack(std::size_t i, std::vector<double>& out, double offset) const {
    const auto& x = local_.component<Position<D>>()[i];
    const auto& v = local_.component<Velocity<D>>()[i];
    for (int a = 0; a < D; ++a) out.push_back(a == D - 1 ? x[a] + offset : x[a]);
    for (int a = 0; a < D; ++a) out.push_back(v[a]);
    if (ids_) out.push_back(local_.component<ParticleId>()[i]);
    if (images_)
      for (int a = 0; a < D; ++a) out.push_back(local_.component<ImageCount<D>>()[i][a]);
  }
  void unpack(const double* in, Vec<D>& x, Vec<D>& v, ParticleId* id, ImageCount<D>* image, std::size_t i) const {
    for (int a = 0; a < D; ++a) x[a] = in[a];
    for (int a = 0; a < D; ++a) v[a] = in[D + a];
    std::size_t k = 2 * D;
    if (ids_) {
      if (id) (*id)[i] = static_cast<std::uint32_t>(in[k]);
      ++k;
    }
    if (images_ && image)
      for (int a = 0; a < D; ++a) (*image)[i][a] = static_cast<std::int32_t>(in[k + static_cast<std::size_t>(a)]);
  }
  // Packed particles appended to this rank's, marked as ghosts or not.
  void append(const std::vector<double>& packed, std::uint8_t ghost) {
    const std::size_t count = packed.size() / width(), first = local_.size();
    if (count == 0) return;
    local_.resize(first + count);
    auto& x = local_.component<Position<D>>();
    auto& v = local_.component<Velocity<D>>();
    ParticleId* id = ids_ ? &local_.component<ParticleId>() : nullptr;
    ImageCount<D>* image = images_ ? &local_.component<ImageCount<D>>() : nullptr;
    auto& mark = local_.component<DomainGhost>();
    for (std::size_t k = 0; k < count; ++k) {
      unpack(packed.data() + k * width(), x[first + k], v[first + k], id, image, first + k);
      mark[first + k] = ghost;
    }
  }
  // Removes the particles whose flag equals `gone`, keeping the others' order.
  template <class Flag>
  void drop(const std::vector<Flag>& flag, Flag gone) {
    std::vector<std::uint32_t> kept;
    kept.reserve(local_.size());
    for (std::size_t i = 0; i < local_.size(); ++i)
      if (flag[i] != gone) kept.push_back(static_cast<std::uint32_t>(i));
    if (kept.size() == local_.size()) return;
    compact(local_.component<Position<D>>().values, kept);
    compact(local_.component<Velocity<D>>().values, kept);
    compact(local_.component<DomainGhost>().values, kept);
    if (ids_) compact(local_.component<ParticleId>().values, kept);
    if (images_) compact(local_.component<ImageCount<D>>().values, kept);
    local_.resize(kept.size());
  }
  template <class T>
  static void compact(std::vector<T>& values, const std::vector<std::uint32_t>& kept) {
    for (std::size_t j = 0; j < kept.size(); ++j) values[j] = values[kept[j]];
  }

  // Particles that streamed out of the slab go towards their owner, the
  // short way round the ring of ranks; those that pass a rank on their way
  // are sent on in the next round.
  void migrate() {
    while (true) {
      std::vector<double> up, down;
      std::vector<std::uint8_t> leaving(local_.size(), 0);
      const auto& x = local_.component<Position<D>>();
      for (std::size_t i = 0; i < local_.size(); ++i) {
        const int owner = slab_.owner(x[i][D - 1]);
        if (owner == slab_.rank) continue;
        const int ahead = (owner - slab_.rank + slab_.ranks) % slab_.ranks;
        pack(i, 2 * ahead <= slab_.ranks ? up : down, 0.0);
        leaving[i] = 1;
      }
      drop(leaving, std::uint8_t{1});
      const std::size_t before = local_.size();
      append(ranks_.exchange(slab_.above(), up, slab_.below(), 0), 0);
      append(ranks_.exchange(slab_.below(), down, slab_.above(), 1), 0);
      bool passing = false;
      for (std::size_t i = before; i < local_.size(); ++i)
        passing = passing || slab_.owner(local_.component<Position<D>>()[i][D - 1]) != slab_.rank;
      if (!ranks_.any(passing)) return;
    }
  }

  // Copies of the neighbours' particles within one cell of this slab's
  // boundaries: every particle of a shifted cell that straddles one.
  void add_ghosts() {
    std::vector<double> to_below, to_above;
    const auto& x = local_.component<Position<D>>();
    const double low = static_cast<double>(slab_.low()), high = static_cast<double>(slab_.high());
    for (std::size_t i = 0; i < local_.size(); ++i) {
      const double z = x[i][D - 1];
      if (z < low + 1.0) pack(i, to_below, slab_.rank == 0 ? length_ : 0.0);
      if (z >= high - 1.0) pack(i, to_above, slab_.rank == slab_.ranks - 1 ? -length_ : 0.0);
    }
    append(ranks_.exchange(slab_.below(), to_below, slab_.above(), 2), 1);
    append(ranks_.exchange(slab_.above(), to_above, slab_.below(), 3), 1);
  }

  const Communicator& ranks_;
  SlabDomain slab_;
  double length_;  // of the periodic box along the slab axis
  World local_;
  SrdStreaming<D> streaming_;
  SrdGridShift<D> shift_;
  SrdCellBinning<D> binning_;
  SrdRotation<D> rotation_;
  bool ids_ = false;
  bool images_ = false;
  bool scattered_ = false;
  bool host_current_ = true;
};

}  // namespace granflow::srd
