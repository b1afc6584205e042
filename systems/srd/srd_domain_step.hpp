#pragma once
// The SRD step of one system spread over the ranks of an MPI job
// (`mpirun -np K granflow run`): each rank owns the particles of one slab of
// cells along a periodic axis (slab_domain.hpp) and steps them with what one
// rank runs (the streaming kernels, the grid shift, binning, reduction,
// rotation and thermostat systems), on a grid of its slab and two layers
// either side; walls lie across the other axes, so every rank has their
// whole length and handles them as one rank does. Per step:
//
//  - streaming (between the walls, under the body force), then the
//    particles that left the slab go to the rank that
//    owns them now (a particle fast enough to cross a whole slab is passed
//    on in further rounds);
//  - the shifted cells that straddle a slab boundary hold particles of two
//    ranks: each rank receives copies of its neighbours' particles in them
//    (ghosts, one layer of cells in all), so that it reduces and rotates
//    those cells over all their particles, as one rank would;
//  - each cell's random rotation, and the wall's ghost particles in a cell
//    it cuts, are keyed by its cell of the whole grid (SrdCells::cell_key),
//    so every rank draws one rank's numbers;
//  - the global thermostat, the energy ledger and the every-step samplers'
//    sums (SrdStepSums) add the sums of each rank's own particles and cells
//    (a straddling cell is the rank's that holds its lower edge) over the
//    ranks, in rank order.
//
// Every balance.every_steps the ranks count each slab's load and, where it
// is uneven, move the bounds (DomainBalance, SlabDomain::balanced) and pass
// every particle to its new owner; where the shear planes lie at the slabs'
// periodic edge (2D), a copy sent across it is moved into its image there.
//
// What stays the same as on one rank and what does not: the random numbers,
// the cells and the particles in each are the same; a straddling cell's
// sums are taken over the same particles in another order, and so are the
// thermostat's and the ledger's, so the results agree to round-off
// (measured in docs/srd.md), not bit for bit. On the same
// number of ranks a run is bit for bit the same on any thread count, and
// resumes bit for bit.
//
// Observers run on every rank over its own part: lend_part puts the rank's
// particles, and its grid's cells as the reduction left them before the
// rotation, into the World, and the observers total their sums over the
// ranks (engine/core/observed_part.hpp). No rank holds the whole system
// then. A checkpoint is written from the same lent parts, each rank's rows
// in rank order (write_checkpoint_by_rank), and a resumed run reads each
// rank's slab back from it by block (Run::initial_state), in the order it
// held them. An observer that cannot run by rank reads the whole on rank
// 0: synchronise_host gathers every rank's particles into it, in rank
// order, with the whole grid's cells, as on one rank; rank 0 observes alone
// and shares its decisions (Run::run_observers), and lets the whole go at
// the next step.

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "components/clock.hpp"
#include "components/image_count.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/communicator.hpp"
#include "engine/core/observed_part.hpp"
#include "engine/core/phase_times.hpp"
#include "engine/core/profiler.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/cell_binning.hpp"
#include "systems/srd/cell_reduction.hpp"
#include "systems/srd/grid_shift.hpp"
#include "systems/srd/rotation.hpp"
#include "systems/geometry/slab_domain.hpp"
#include "systems/srd/srd_cells.hpp"
#include "systems/srd/srd_kernels.hpp"
#include "systems/srd/srd_step_sums.hpp"
#include "systems/srd/srd_walls.hpp"
#include "systems/srd/streaming.hpp"
#include "systems/srd/thermostat.hpp"
#include "engine/run/run_control.hpp"

namespace granflow::srd {

inline const SystemDescription srd_domain_step_description{
    "srd_domain_step",
    "the SRD step over MPI ranks: slabs of cells, particles migrated and ghost layers exchanged every step"};

// Marks a rank's copies of its neighbours' particles for the current step.
struct DomainGhost : Column<std::uint8_t> {
  static constexpr const char* key = "domain_ghost";
};

// What the step does besides the periodic SRD step.
template <int D>
struct DomainStepPhysics {
  int axis = D - 1;  // of the slabs: periodic, not x where there is shear
  double shear_rate = 0.0;  // through Lees-Edwards planes across y
  BodyForce<D> force;
  double thermostat_temperature = 0.0;  // 0: none
  bool remove_drift = true;             // the thermostat's: false between walls
  // The World holds this rank's slab from the start (add_srd_fluid), not
  // the whole system: the first gather then builds rank 0's whole.
  bool started_by_slab = false;
};

// When the slabs are rebalanced: every `every_steps` (0: never) each
// slab's load is counted, its particles plus `cell_weight` times its cells
// (a cell's rotation and reduction cost several particles' whole step), and
// where the busiest rank's exceeds `threshold` times the mean the bounds
// move (SlabDomain::balanced). A count, not a timing, so that the bounds and
// the result do not depend on the machine's speed. `kept` carries the
// bounds in checkpoints.
struct DomainBalance {
  std::int64_t every_steps = 0;
  double threshold = 1.1;
  double cell_weight = 0.0;
  std::shared_ptr<SlabBounds> kept;
};

template <int D>
using SrdDomainStepBase = SystemOf<Reads<>, Writes<EveryColumn, Clock, SrdCells<D>, SrdStepSums<D>, RunControl>>;

template <int D>
class SrdDomainStep : public SrdDomainStepBase<D> {
 public:
  using View = typename SrdDomainStepBase<D>::View;

  SrdDomainStep(const Communicator& ranks, double dt, const RotationParameters& rotation, std::uint64_t seed,
                bool grid_shift, std::uint64_t reorder_interval, const SrdCells<D>& whole,
                const DomainStepPhysics<D>& physics, DomainBalance balance = {})
      : ranks_(ranks),
        axis_(physics.axis),
        physics_(physics),
        slab_(ranks.rank(), ranks.size(), whole.cells[physics.axis], axis_names[physics.axis]),
        length_(whole.length[physics.axis]),
        length_x_(whole.length[0]),
        low_(static_cast<double>(slab_.low())),
        high_(static_cast<double>(slab_.high())),
        dt_(dt),
        shift_(seed, grid_shift),
        binning_(reorder_interval),
        rotation_(rotation, seed),
        reorder_interval_(reorder_interval),
        balance_(std::move(balance)) {
    local_.emplace_resource<Clock>();
    rotation_.quiet();  // report_clamping warns for all ranks
    host_current_ = !physics.started_by_slab;
    place_grid(whole);
    periodic_ = ~whole.bounded;
    accounts_ = !whole.walls.empty() || whole.record_energy;
  }

  std::string name() const override { return "srd_domain_step"; }

  // This rank's grid: the box, but along the slab axis the slab and two
  // layers either side; the walls give their axes' grids as on one rank.
  // `like` (the whole grid, or this rank's before its slab moved) gives the
  // rest.
  void place_grid(const SrdCells<D>& like) {
    std::array<std::int32_t, D> dims{};
    for (int a = 0; a < D; ++a) dims[a] = static_cast<std::int32_t>(like.length[a]);
    const auto low = slab_.low(), width = slab_.high() - slab_.low();
    dims[axis_] = static_cast<std::int32_t>(width + 4);
    SrdCells<D> cells(dims, 0, like.walls);
    cells.length = like.length;
    cells.origin[axis_] = static_cast<double>(low - 2);
    cells.bounded |= 1u << axis_;  // its own grid ends at the halo: no wrap there
    cells.shift = like.shift;
    cells.shear = like.shear;
    cells.particle_mass = like.particle_mass;
    cells.ghost_fill = like.ghost_fill;
    cells.seed = like.seed;
    cells.record_energy = like.record_energy;
    cells.record_moments = like.record_moments;
    cells.part_of_whole = {axis_, low - 2, slab_.cells, low, slab_.high()};
    local_.emplace_resource<SrdCells<D>>(std::move(cells));
  }

  void run_on(View view) override {
    if (!scattered_) scatter(view);
    // A whole that a round gathered onto rank 0 is stale once the step moves on.
    if (view.size() > 0) {
      view.release();
      view.template write<SrdCells<D>>().release_arrays();
    }
    stepped_ = true;
    const auto now = local_.resource<Clock>().step;
    if (balance_.every_steps > 0 && now > 0 && now % balance_.every_steps == 0) timed(10, [&] { rebalance(); });
    auto& clock = local_.resource<Clock>();
    const double start = clock.time;
    clock.advance(dt_);
    SrdStreaming<D>::set_shear(local_.resource<SrdCells<D>>(), physics_.shear_rate, clock.time);
    shear_ = local_.resource<SrdCells<D>>().shear;
    shift_.run(local_);  // first: it tells which particles are ghosts
    timed(0, [&] { stream_and_sort_out(start); });
    // The first round of the migration travels while this rank assigns its
    // own particles' cells (not on the steps that sort them all).
    const auto step = static_cast<std::uint64_t>(local_.resource<Clock>().step);
    const bool sorting = reorder_interval_ > 0 && step % reorder_interval_ == 0;
    timed(1, [&] { start_migration(); });
    const std::size_t assigned = sorting ? 0 : local_.size();
    if (!sorting)
      timed(3, [&] { SrdCellBinning<D>::assign(local_.component<Position<D>>(), local_.resource<SrdCells<D>>()); });
    timed(1, [&] { finish_migration(); });
    const std::size_t owned = local_.size();
    timed(2, [&] { add_ghosts(); });
    timed(3, [&] {
      if (sorting) binning_.run(local_);
      else SrdCellBinning<D>::assign(local_.component<Position<D>>(), local_.resource<SrdCells<D>>(), assigned);
    });
    timed(4, [&] { SrdCellReduction<D>::reduce(local_, local_.resource<SrdCells<D>>()); });
    local_.resource<SrdCells<D>>().copies = local_.component<DomainGhost>().data();
    timed(5, [&] {
      rotation_.run(local_);
      if (physics_.thermostat_temperature > 0.0) thermostat();
    });
    if (accounts_) account(view);
    fill_step_sums(view);
    // The ghosts were appended last: unless this step's reordering mixed
    // them in, dropping them is a truncation.
    timed(6, [&] {
      if (sorting) drop(local_.component<DomainGhost>().values, std::uint8_t{1});
      else local_.resize(owned);
      // Room for the next step's ghosts and arrivals (a few per cent), kept
      // through the sorts: else growing into them moves every column, on
      // one rank while the other waits. A no-op once the room is there.
      const std::size_t room = local_.size() + local_.size() / 16;
      local_.reserve(room);
      auto& cells = local_.resource<SrdCells<D>>();
      cells.cell.reserve(room);
      if (!cells.image.empty()) cells.image.reserve(room);
    });
    finish_agreement();
    view.template write<Clock>() = local_.resource<Clock>();
    view.template write<SrdCells<D>>().shift = local_.resource<SrdCells<D>>().shift;
    view.template write<SrdCells<D>>().shear = local_.resource<SrdCells<D>>().shear;
    host_current_ = false;
  }

  // Every rank's particles into the whole World on rank 0, and the whole
  // grid's cells from them.
  void synchronise_host(World& whole) override {
    if (host_current_) return;
    if (!scattered_) scatter(View(whole));
    // Column by column, straight from the rank's columns into rank 0's: no
    // rank packs a copy of its particles, and rank 0 none of the whole.
    const std::size_t own = local_.size();
    const bool first = ranks_.rank() == 0;
    std::size_t n = 0;
    timed(7, [&] {
      for (const std::int64_t count : ranks_.counts_on_first(static_cast<std::int64_t>(own)))
        n += static_cast<std::size_t>(count);
    });
    if (first) whole.resize(n);
    const auto gather = [&](const double* mine, std::size_t width, double* all) {
      timed(7, [&] { ranks_.gather_to_first(mine, own, width, all); });
    };
    // Integer columns travel as doubles (exact below 2^53).
    const auto gather_integers = [&](const auto* mine, std::size_t width, auto* all) {
      const std::vector<double> values(mine, mine + own * width);
      std::vector<double> gathered(first ? n * width : 0);
      gather(values.data(), width, gathered.data());
      using Integer = std::remove_pointer_t<decltype(all)>;
      for (std::size_t k = 0; k < gathered.size(); ++k) all[k] = static_cast<Integer>(gathered[k]);
    };
    gather(values_of<Position<D>>(local_), D, first ? values_of<Position<D>>(whole) : nullptr);
    gather(values_of<Velocity<D>>(local_), D, first ? values_of<Velocity<D>>(whole) : nullptr);
    if (ids_) gather_integers(values_of<ParticleId>(local_), 1, first ? values_of<ParticleId>(whole) : nullptr);
    if (images_)
      gather_integers(values_of<ImageCount<D>>(local_), D, first ? values_of<ImageCount<D>>(whole) : nullptr);
    const auto clamped = ranks_.sum(static_cast<std::int64_t>(local_.resource<SrdCells<D>>().clamped_cells));
    report_clamping();
    if (!first) {
      if (stepped_) gather_cells(nullptr);
      host_current_ = true;
      return;
    }
    auto& x = whole.component<Position<D>>();
    auto& cells = whole.resource<SrdCells<D>>();
    if (cells.cell_count() == 0) cells.allocate_arrays(n);
    SrdCellBinning<D>::assign(x, cells);
    // Before the first step the cells are the initial state's, from the
    // whole system as on one rank (the slabs have reduced none yet).
    if (stepped_) gather_cells(&cells);
    else SrdCellReduction<D>::reduce(whole, cells);
    cells.clamped_cells = static_cast<std::uint64_t>(clamped);
    host_current_ = true;
  }

  // This rank's own particles, and this step's cells of its grid (as the
  // reduction left them, as synchronise_host gives the whole), lent to the
  // World for observers that run by rank: its columns and cells trade
  // places with the World's until take_back_part. Before the first step
  // the rank reduces its own particles alone, which gives its cells of the
  // whole grid where no shifted cell straddles a slab boundary: with no
  // shift along the slab axis (a fresh start; a resumed one gathers).
  bool lend_part(World& world) override {
    if (!scattered_) scatter(View(world));
    auto& cells = local_.resource<SrdCells<D>>();
    if (!stepped_ && cells.shift[axis_] != 0.0) return false;
    if (world.column_count() != std::size_t{2} + (ids_ ? 1 : 0) + (images_ ? 1 : 0)) return false;
    SrdCellBinning<D>::assign(local_.component<Position<D>>(), cells);
    if (!stepped_) SrdCellReduction<D>::reduce(local_, cells);
    const std::size_t own = local_.size();
    const auto clamped = ranks_.sum(static_cast<std::int64_t>(cells.clamped_cells));
    report_clamping();
    world_size_ = world.size();
    trade_part(world);
    world.resize(own);
    // The run's and this step's totals over the ranks, as the World had them.
    auto& lent = world.resource<SrdCells<D>>();
    own_totals_ = totals_of(lent);
    set_totals(lent, totals_of(local_.resource<SrdCells<D>>()));
    lent.clamped_cells = static_cast<std::uint64_t>(clamped);
    world.emplace_resource<ObservedPart>(ranks_, axis_, slab_.low(), slab_.high());
    return true;
  }
  void take_back_part(World& world) override {
    trade_part(world);
    world.resize(world_size_);
    set_totals(local_.resource<SrdCells<D>>(), own_totals_);
  }

  // The every-step sums rank 0's samplers asked for, for the other ranks,
  // which add their particles' part (fill_step_sums) though they observe
  // nothing: [stress asked, then axis, flow and layers of each request].
  std::vector<double> observers_requests(const World& whole) const override {
    if (!whole.has_resource<SrdStepSums<D>>()) return {};
    const auto& sums = whole.resource<SrdStepSums<D>>();
    std::vector<double> out{sums.stress_requested ? 1.0 : 0.0};
    for (const LayerSumsRequest& r : sums.layer_requests)
      out.insert(out.end(), {static_cast<double>(r.axis), static_cast<double>(r.flow), static_cast<double>(r.layers)});
    return out;
  }
  void adopt_observers_requests(World& whole, const std::vector<double>& asked) override {
    if (asked.empty() || !whole.has_resource<SrdStepSums<D>>()) return;
    auto& sums = whole.resource<SrdStepSums<D>>();
    sums.stress_requested = asked[0] != 0.0;
    sums.layer_requests.clear();
    for (std::size_t k = 1; k + 3 <= asked.size(); k += 3)
      sums.layer_requests.push_back(
          {static_cast<int>(asked[k]), static_cast<int>(asked[k + 1]), static_cast<int>(asked[k + 2])});
  }

  // The time in each part of the step: this rank's as the step's own rows
  // (rank 0's reach the profile), and every rank's as rows
  // `srd_domain_step.rank<r>.<part>`, so that a slow rank and the others'
  // wait for it show. Collective: every rank writes its results.
  std::vector<ProfileEntry> device_profile() const override {
    report_clamping();
    return times_.entries("srd_domain_step", ranks_);
  }

 private:
  // Time in MPI calls, waiting for the other ranks included: the exchanges
  // with the neighbours and the per-step sums (inside the parts above);
  // apart, the sum each round of the migration ends with, which agrees on
  // further rounds and on a signal.
  template <class Work>
  void communicating(Work&& work) {
    timed(8, std::forward<Work>(work));
  }
  template <class Work>
  void agreeing(Work&& work) {
    timed(9, std::forward<Work>(work));
  }
  template <class Work>
  void timed(std::size_t phase, Work&& work) {
    times_.timed(phase, std::forward<Work>(work));
  }

  std::size_t width() const { return 2 * D + (ids_ ? 1 : 0) + (images_ ? D : 0); }

  // The rotation's warning of cells clamped at eps_eff = 0, as one rank
  // gives it: the first step any rank clamped cells and all ranks' cells of
  // that step, said by rank 0 once, at the first collective round after it
  // (an output, a checkpoint or the end). Collective.
  void report_clamping() const {
    if (clamping_reported_) return;
    const std::vector<double> all = ranks_.gather_all(
        {static_cast<double>(rotation_.first_clamped_step()), static_cast<double>(rotation_.first_clamped_cells())});
    double first = -1.0, cells = 0.0;
    for (std::size_t r = 0; r + 1 < all.size(); r += 2)
      if (all[r] >= 0.0 && (first < 0.0 || all[r] < first)) first = all[r];
    if (first < 0.0) return;
    for (std::size_t r = 0; r + 1 < all.size(); r += 2)
      if (all[r] == first) cells += all[r + 1];
    clamping_reported_ = true;
    if (ranks_.rank() == 0) warn_clamped_cells(static_cast<std::int64_t>(first), static_cast<std::uint64_t>(cells));
  }

  // What the cells count over the run and the step, besides their arrays.
  struct Totals {
    std::uint64_t wall_reflections = 0, clamped_cells = 0;
    double wall_work = 0.0, collision_energy = 0.0, ghost_cell_energy = 0.0;
  };
  static Totals totals_of(const SrdCells<D>& cells) {
    return {cells.wall_reflections, cells.clamped_cells, cells.step_wall_work, cells.step_collision_energy,
            cells.step_ghost_cell_energy};
  }
  static void set_totals(SrdCells<D>& cells, const Totals& t) {
    cells.wall_reflections = t.wall_reflections;
    cells.clamped_cells = t.clamped_cells;
    cells.step_wall_work = t.wall_work;
    cells.step_collision_energy = t.collision_energy;
    cells.step_ghost_cell_energy = t.ghost_cell_energy;
  }

  // The particle columns and the cells, between this rank's and the World's.
  void trade_part(World& world) {
    std::swap(local_.component<Position<D>>().values, world.component<Position<D>>().values);
    std::swap(local_.component<Velocity<D>>().values, world.component<Velocity<D>>().values);
    if (ids_) std::swap(local_.component<ParticleId>().values, world.component<ParticleId>().values);
    if (images_) std::swap(local_.component<ImageCount<D>>().values, world.component<ImageCount<D>>().values);
    std::swap(local_.resource<SrdCells<D>>(), world.resource<SrdCells<D>>());
  }

  // Column C's values as scalars: its first element's, null where it is empty.
  template <class C>
  static auto* values_of(World& world) {
    auto& values = world.component<C>().values;
    using Scalar = std::remove_pointer_t<decltype(scalars(values.data()))>;
    return values.empty() ? static_cast<Scalar*>(nullptr) : scalars(values.data());
  }
  template <class T>
  static auto* scalars(T* first) {
    if constexpr (std::is_arithmetic_v<T>) return first;
    else return first->data();
  }

  // This step's cells (as the reduction left them, before the rotation, with
  // the rotation's collisional transfer) into the whole grid on rank 0
  // (`whole` is null on the others), each from the rank that owns it.
  void gather_cells(SrdCells<D>* whole) const {
    const auto& local = local_.resource<SrdCells<D>>();
    constexpr std::size_t record = 5 + D;
    std::vector<double> mine;
    for (std::size_t c = 0; c < local.cell_count(); ++c) {
      if (!local.owns(c)) continue;
      mine.push_back(static_cast<double>(local.cell_key(c)));
      mine.push_back(local.count[c]);
      mine.push_back(local.mass[c]);
      mine.push_back(local.theta[c]);
      mine.push_back(local.transfer[c]);
      for (int a = 0; a < D; ++a) mine.push_back(local.velocity[c][a]);
    }
    const std::vector<double> all = ranks_.gather_to_first(mine);
    if (!whole) return;
    for (std::size_t r = 0; r + record <= all.size(); r += record) {
      const auto c = static_cast<std::size_t>(all[r]);
      whole->count[c] = static_cast<std::uint32_t>(all[r + 1]);
      whole->mass[c] = all[r + 2];
      whole->theta[c] = all[r + 3];
      whole->transfer[c] = all[r + 4];
      for (int a = 0; a < D; ++a) whole->velocity[c][a] = all[r + 5 + static_cast<std::size_t>(a)];
    }
  }

  // This rank's particles of the whole World (the initial state, or the one
  // a checkpoint restored), in the World's order.
  void scatter(View view) {
    // A checkpoint's bounds, where it was written on as many ranks; else
    // the equal slabs, which the next checkpoint then carries.
    if (balance_.kept && balance_.kept->bounds.size() == slab_.bounds.size()) set_bounds(balance_.kept->bounds);
    if (balance_.kept) balance_.kept->bounds = slab_.bounds;
    const auto& x = view.template read<Position<D>>();
    const auto& v = view.template read<Velocity<D>>();
    ids_ = view.template has<ParticleId>();
    images_ = view.template has<ImageCount<D>>();
    local_.add_component<Position<D>>();
    local_.add_component<Velocity<D>>();
    local_.add_component<DomainGhost>();
    if (ids_) local_.add_component<ParticleId>();
    if (images_) local_.add_component<ImageCount<D>>();
    if (physics_.started_by_slab) {
      // The World holds this slab's particles in order: its columns become
      // the rank's, and rank 0's whole comes with its first gather.
      const std::size_t n = view.size();
      std::swap(local_.component<Position<D>>().values, view.template write<Position<D>>().values);
      std::swap(local_.component<Velocity<D>>().values, view.template write<Velocity<D>>().values);
      if (ids_) std::swap(local_.component<ParticleId>().values, view.template write<ParticleId>().values);
      if (images_) std::swap(local_.component<ImageCount<D>>().values, view.template write<ImageCount<D>>().values);
      local_.resize(n);
      view.release();
      finish_scatter(view);
      return;
    }
    std::vector<double> mine;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (slab_.owner(x[i][axis_]) != slab_.rank) continue;
      for (int a = 0; a < D; ++a) mine.push_back(x[i][a]);
      for (int a = 0; a < D; ++a) mine.push_back(v[i][a]);
      if (ids_) mine.push_back(view.template read<ParticleId>()[i]);
      if (images_)
        for (int a = 0; a < D; ++a) mine.push_back(view.template read<ImageCount<D>>()[i][a]);
    }
    append(mine, 0);
    finish_scatter(view);
  }
  void finish_scatter(View view) {
    local_.resource<Clock>() = view.template read<Clock>();
    scattered_ = true;
    // No rank needs the whole any more, neither its particles nor its
    // grid's arrays: rank 0 makes them again where a round gathers.
    view.release();
    view.template write<SrdCells<D>>().release_arrays();
    host_current_ = false;
  }

  // The local columns, looked up once per pass rather than per particle.
  struct Columns {
    Vec<D>* x;
    Vec<D>* v;
    std::uint32_t* id;
    typename ImageCount<D>::value_type* image;
  };
  Columns columns() {
    return {local_.component<Position<D>>().data(), local_.component<Velocity<D>>().data(),
            ids_ ? local_.component<ParticleId>().data() : nullptr,
            images_ ? local_.component<ImageCount<D>>().data() : nullptr};
  }

  // Particle i's columns onto `out`, moved by `offset` (0 or +-the box)
  // along the slab axis, into the frame of the rank across the periodic
  // edge. Where that edge is a Lees-Edwards plane (slabs along y), the image
  // above moves by the shear's offset and velocity along x: seen from there
  // the particle is where a one-rank grid's cell across the plane sees it
  // (srd_kernels.hpp: cell_of, image_velocity_x).
  void pack(const Columns& c, std::size_t i, std::vector<double>& out, double offset) const {
    const Shear& shear = shear_;
    const double image = axis_ == 1 && shear.velocity != 0.0 ? (offset > 0.0 ? 1.0 : (offset < 0.0 ? -1.0 : 0.0)) : 0.0;
    for (int a = 0; a < D; ++a) {
      if (a == axis_) out.push_back(c.x[i][a] + offset);
      else if (a == 0 && image != 0.0) out.push_back(wrapped(c.x[i][a] + image * shear.offset, length_x_));
      else out.push_back(c.x[i][a]);
    }
    for (int a = 0; a < D; ++a) out.push_back(a == 0 ? c.v[i][a] + image * shear.velocity : c.v[i][a]);
    if (c.id) out.push_back(c.id[i]);
    if (c.image)
      for (int a = 0; a < D; ++a) out.push_back(c.image[i][a]);
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

  // Streams every particle (the periodic streaming of streaming.hpp) and in
  // the same pass, while the particle is in cache, notes which leave the
  // slab and which the neighbours need as ghosts: per fixed chunk, so that
  // the lists come out in particle order on any thread count.
  void stream_and_sort_out(double start) {
    const auto& cells = local_.resource<SrdCells<D>>();
    const double shift = cells.shift[axis_];
    const double part_below = shift - std::floor(shift);
    // The shifted cell that straddles a slab boundary reaches part_below =
    // frac(shift) below it and 1 - part_below above it (none straddles when
    // the shift is a whole number of cells). A particle within round-off of
    // its far edge is sent too: there it falls into a cell that holds none
    // of the receiver's own.
    constexpr double margin = 1e-9;
    ghost_below_edge_ = part_below > 0.0 ? low_ + (1.0 - part_below) + margin : low_;
    ghost_above_edge_ = part_below > 0.0 ? high_ - part_below - margin : high_;
    // This rank's own straddling cells beyond its slab (nothing where none straddles).
    keep_below_edge_ = part_below > 0.0 ? low_ - part_below - margin : low_;
    keep_above_edge_ = part_below > 0.0 ? high_ + (1.0 - part_below) + margin : high_;
    const std::size_t n = local_.size();
    constexpr std::size_t chunk = 4096;
    const std::size_t chunks = (n + chunk - 1) / chunk;
    sorted_out_.resize(chunks);
    const Columns c = columns();
    const Shear shear = cells.shear;
    const WalledFlight<D> flight{cells.walls.data(), static_cast<int>(cells.walls.size()), periodic_, physics_.force,
                                 start, dt_, cells.length.data()};
    const SlabEdges edges{axis_, low_, high_, ghost_below_edge_, ghost_above_edge_};
    const bool walled = !cells.walls.empty() || physics_.force.any();
    const bool work = cells.record_energy;
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
      auto& lists = sorted_out_[k];
      lists.leaving.clear();
      lists.below.clear();
      lists.above.clear();
      lists.reflections = lists.stranded = 0;
      lists.work = 0.0;
      const std::size_t first = k * chunk, end = std::min(n, (k + 1) * chunk);
      if (walled) {
        stream_chunk(first, end, c, edges, lists, [&](std::size_t i, double* x, double* v) {
          const int reflections = flight(x, v, c.image ? c.image[i].data() : nullptr, work ? &lists.work : nullptr);
          lists.reflections += static_cast<std::uint64_t>(reflections);
          lists.stranded += reflections == most_reflections ? 1 : 0;
        });
      } else if (c.image) {
        stream_chunk(first, end, c, edges, lists, [&](std::size_t i, double* x, double* v) {
          stream_particle<D, true>(x, v, flight.dt, flight.length, shear, c.image[i].data());
        });
      } else {
        stream_chunk(first, end, c, edges, lists, [&](std::size_t, double* x, double* v) {
          stream_particle<D>(x, v, flight.dt, flight.length, shear);
        });
      }
    });
  }

  // Per chunk of particles, from the streaming pass: those leaving the slab
  // and those the neighbour below / above needs as ghosts.
  struct SortedOut {
    std::vector<std::size_t> leaving, below, above;
    std::uint64_t reflections = 0, stranded = 0;
    double work = 0.0;  // by the walls, per unit mass
  };
  // This step's edges along the slab axis, as values: the streaming loop
  // writes positions through pointers, which could otherwise alias the
  // members and have them read again for every particle.
  struct SlabEdges {
    int axis;
    double low, high, ghost_below, ghost_above;
  };
  // Streams particles [first, end) with `move` and sorts out those that
  // left the slab and those the neighbours need as ghosts.
  template <class Move>
  void stream_chunk(std::size_t first, std::size_t end, const Columns& c, const SlabEdges edges, SortedOut& lists,
                    Move&& move) const {
    for (std::size_t i = first; i < end; ++i) {
      double* x = c.x[i].data();
      move(i, x, c.v[i].data());
      const double z = x[edges.axis];
      if (z < edges.ghost_below || z >= edges.ghost_above) [[unlikely]] {
        if (!(z >= edges.low && z < edges.high) && slab_.owner(z) != slab_.rank) {
          lists.leaving.push_back(i);
          continue;
        }
        if (z < edges.ghost_below) lists.below.push_back(i);
        if (z >= edges.ghost_above) lists.above.push_back(i);
      }
    }
  }

  // Particles that streamed out of the slab go towards their owner, the
  // short way round the ring of ranks, in one message per neighbour with
  // the ghosts that neighbour needs: [migrant count, migrants, ghosts].
  // Most ghosts were picked in the streaming pass. A rank keeps a copy of a
  // particle it sends away into its own straddling cells (the receiver
  // cannot know it needs sending back), and an arrival that lands in the
  // straddling cells of the neighbour on the far side, or is only passing
  // through, goes on in a further round, which every rank agrees on. The
  // rebalance migrates in one go; the step starts the first round, works,
  // and then finishes it.
  void migrate() {
    start_migration();
    finish_migration();
    finish_agreement();
  }
  void finish_agreement() {
    if (!agreement_open_) return;
    agreement_open_ = false;
    agreeing([&] { ranks_.finish_agreeing_on_interrupt(agreement_); });
  }
  // Packs the first round, removes the leavers and sends (once the
  // neighbours have read the last step's messages).
  void start_migration() {
    communicating([&] { ranks_.wait_sent(exchange_); });
    to_below_.clear();
    to_above_.clear();
    arrived_ghosts_.clear();
    kept_.clear();
    up_.clear();
    down_.clear();
    gone_.clear();
    {
      const Columns c = columns();
      for (const auto& lists : sorted_out_) {
        for (const std::size_t i : lists.below) pack(c, i, to_below_, slab_.rank == 0 ? length_ : 0.0);
        for (const std::size_t i : lists.above) pack(c, i, to_above_, slab_.rank == slab_.ranks - 1 ? -length_ : 0.0);
        for (const std::size_t i : lists.leaving) send_away(c, i, up_, down_, gone_);
      }
    }
    remove(gone_);
    gone_.clear();
    exchange_.below = slab_.below();
    exchange_.above = slab_.above();
    exchange_.down = message(down_, to_below_);
    exchange_.up = message(up_, to_above_);
    communicating([&] { ranks_.start_exchange(exchange_); });
  }
  // Takes the first round's arrivals, then runs the further rounds. On two
  // ranks there are none (what leaves one slab is the other's, and the
  // sender kept its copies), so the agreement on the signal is only started
  // here and finished at the end of the step: a rank then waits for the
  // other only where that one is later than this rank's whole step.
  void finish_migration() {
    Communicator::Received arrived;
    communicating([&] { arrived = ranks_.finish_exchange(exchange_); });
    std::int64_t pending = take_round(arrived);
    if (slab_.ranks == 2) {
      ranks_.start_agreeing_on_interrupt(agreement_, pending);
      agreement_open_ = true;
      return;
    }
    while (true) {
      // Once per round on every rank: the place to agree on a signal too.
      std::int64_t pending_anywhere = 0;
      agreeing([&] { pending_anywhere = ranks_.sum_agreeing_on_interrupt(pending); });
      if (pending_anywhere == 0) return;
      remove(gone_);
      gone_.clear();
      communicating([&] {
        arrived = ranks_.exchange_with_neighbours(slab_.below(), message(down_, to_below_), slab_.above(),
                                                  message(up_, to_above_), 0);
      });
      pending = take_round(arrived);
    }
  }
  // A round's arrivals: the migrants become this rank's and the ghosts are
  // set aside; those that go on are packed for the next round. Returns how
  // many go on.
  std::int64_t take_round(const Communicator::Received& arrived) {
    const std::size_t first = local_.size();
    const std::size_t from_below = take_message(arrived.from_below);
    take_message(arrived.from_above);
    up_.clear();
    down_.clear();
    to_below_.clear();
    to_above_.clear();
    std::int64_t pending = 0;
    const Columns c = columns();
    for (std::size_t i = first; i < local_.size(); ++i) {
      const double z = c.x[i][axis_];
      if (!(z >= low_ && z < high_) && slab_.owner(z) != slab_.rank) {
        send_away(c, i, up_, down_, gone_);
        ++pending;
        continue;
      }
      // The neighbour it came from kept its own copy; on two ranks that
      // is the only neighbour.
      if (slab_.ranks == 2) continue;
      if (i < first + from_below && z >= ghost_above_edge_) {
        pack(c, i, to_above_, slab_.rank == slab_.ranks - 1 ? -length_ : 0.0);
        ++pending;
      }
      if (i >= first + from_below && z < ghost_below_edge_) {
        pack(c, i, to_below_, slab_.rank == 0 ? length_ : 0.0);
        ++pending;
      }
    }
    return pending;
  }

  // Particle i leaves towards its owner; a copy stays if it lies in this
  // rank's own straddling cells.
  void send_away(const Columns& c, std::size_t i, std::vector<double>& up, std::vector<double>& down,
                 std::vector<std::size_t>& gone) {
    const double z = c.x[i][axis_];
    const int ahead = (slab_.owner(z) - slab_.rank + slab_.ranks) % slab_.ranks;
    const bool upward = 2 * ahead <= slab_.ranks;
    pack(c, i, upward ? up : down, 0.0);
    gone.push_back(i);
    // Where it is seen from this slab, below it or above it (across the
    // periodic edge where need be; on two ranks either way round).
    const double below = z >= low_ ? z - length_ : z, above = z < high_ ? z + length_ : z;
    if (below >= keep_below_edge_) pack(c, i, kept_, below - z);
    if (above < keep_above_edge_) pack(c, i, kept_, above - z);
  }

  std::vector<double> message(const std::vector<double>& migrants, const std::vector<double>& ghosts) const {
    std::vector<double> out;
    out.reserve(1 + migrants.size() + ghosts.size());
    out.push_back(static_cast<double>(migrants.size() / width()));
    out.insert(out.end(), migrants.begin(), migrants.end());
    out.insert(out.end(), ghosts.begin(), ghosts.end());
    return out;
  }
  // Appends a message's migrants as this rank's own and sets its ghosts
  // aside; returns the number of migrants.
  std::size_t take_message(const std::vector<double>& in) {
    if (in.empty()) return 0;
    const auto migrants = static_cast<std::size_t>(in[0]);
    const auto split = in.begin() + 1 + static_cast<std::ptrdiff_t>(migrants * width());
    append(std::vector<double>(in.begin() + 1, split), 0);
    arrived_ghosts_.insert(arrived_ghosts_.end(), split, in.end());
    return migrants;
  }

  // Removes the particles at `gone` (ascending) by moving the last ones into
  // their places: a few particles leave a slab per step, and this moves no
  // more than that many.
  void remove(const std::vector<std::size_t>& gone) {
    if (gone.empty()) return;
    // Whether particle i leaves too, for i falling from the end: `gone` is
    // ascending, so its tail is read once, not marked in a column of all.
    std::size_t tail = gone.size();
    const auto leaves = [&](std::size_t i) {
      while (tail > 0 && gone[tail - 1] > i) --tail;
      return tail > 0 && gone[tail - 1] == i;
    };
    Columns c = columns();
    auto* ghost = local_.component<DomainGhost>().data();
    std::size_t end = local_.size();
    for (const std::size_t hole : gone) {
      if (hole >= end) break;
      do --end;
      while (end > hole && leaves(end));
      if (end == hole) break;
      c.x[hole] = c.x[end];
      c.v[hole] = c.v[end];
      ghost[hole] = ghost[end];
      if (c.id) c.id[hole] = c.id[end];
      if (c.image) c.image[hole] = c.image[end];
    }
    local_.resize(end);
  }

  void set_bounds(const std::vector<std::int64_t>& bounds) {
    slab_.bounds = bounds;
    low_ = static_cast<double>(slab_.low());
    high_ = static_cast<double>(slab_.high());
    place_grid(local_.resource<SrdCells<D>>());
    if (balance_.kept) balance_.kept->bounds = bounds;
  }

  // Counts the load of every layer along the slab axis (all ranks alike)
  // and, where the busiest rank's exceeds the threshold times the mean,
  // moves the bounds and passes every particle to its new owner.
  void rebalance() {
    std::vector<double> per_layer(static_cast<std::size_t>(slab_.cells), 0.0);
    {
      const Columns c = columns();
      for (std::size_t i = 0; i < local_.size(); ++i) {
        const auto k = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(c.x[i][axis_])), 0, slab_.cells - 1);
        per_layer[static_cast<std::size_t>(k)] += 1.0;
      }
    }
    communicating([&] { per_layer = ranks_.add_across(per_layer); });
    double cells_per_layer = 1.0;
    for (int a = 0; a < D; ++a)
      if (a != axis_) cells_per_layer *= static_cast<double>(local_.resource<SrdCells<D>>().cells[a]);
    for (double& load : per_layer) load += balance_.cell_weight * cells_per_layer;
    const auto busiest = [&](const std::vector<std::int64_t>& bounds) {
      double total = 0.0, most = 0.0;
      for (const double n : SlabDomain::loads(per_layer, bounds)) {
        total += n;
        most = std::max(most, n);
      }
      return total > 0.0 ? most * static_cast<double>(slab_.ranks) / total : 1.0;
    };
    const double before = busiest(slab_.bounds);
    if (before <= balance_.threshold) return;
    const auto bounds = SlabDomain::balanced(per_layer, slab_.ranks);
    if (bounds == slab_.bounds) return;
    spdlog::info("step {}: the slabs rebalanced, the busiest rank's load from {:.3f} to {:.3f} times the mean",
                 local_.resource<Clock>().step, before, busiest(bounds));
    times_.timed(11, [&] {
      set_bounds(bounds);
      redistribute();
    });
  }

  // Every particle to the owner of its slab, through the migration's rounds,
  // with no ghosts and no copies kept.
  void redistribute() {
    constexpr double inf = std::numeric_limits<double>::infinity();
    ghost_below_edge_ = -inf;
    ghost_above_edge_ = inf;
    keep_below_edge_ = inf;
    keep_above_edge_ = -inf;
    sorted_out_.assign(1, {});
    const Columns c = columns();
    for (std::size_t i = 0; i < local_.size(); ++i)
      if (slab_.owner(c.x[i][axis_]) != slab_.rank) sorted_out_[0].leaving.push_back(i);
    migrate();
    arrived_ghosts_.clear();
    kept_.clear();
  }

  // The global thermostat over the ranks: each rank's own particles and cells.
  void thermostat() {
    auto& cells = local_.resource<SrdCells<D>>();
    const std::uint8_t* copy = local_.component<DomainGhost>().data();
    SrdThermostat<D>::rescale(
        local_.component<Velocity<D>>().data(), nullptr, local_.size(), cells, physics_.thermostat_temperature,
        physics_.remove_drift, [copy](std::size_t i) { return copy[i] == 0; },
        [&](std::size_t c) { return cells.owns(c); }, [&](std::vector<double> sums) { return ranks_.add_across(sums); });
  }

  // The step's wall reflections, stranded particles and energies, added
  // over the ranks into the whole grid's cells (which the energy ledger and
  // the observers read) on every rank; a stranded particle on any rank stops
  // the run on all.
  void account(View view) {
    const auto& cells = local_.resource<SrdCells<D>>();
    std::vector<double> sums(5, 0.0);
    for (const auto& lists : sorted_out_) {
      sums[0] += static_cast<double>(lists.reflections);
      sums[1] += static_cast<double>(lists.stranded);
      sums[2] += lists.work;
    }
    sums[2] *= cells.particle_mass;
    sums[3] = cells.step_collision_energy;
    sums[4] = cells.step_ghost_cell_energy;
    communicating([&] { sums = ranks_.add_across(sums); });
    auto& whole = view.template write<SrdCells<D>>();
    whole.wall_reflections += static_cast<std::uint64_t>(sums[0]);
    whole.step_wall_work = sums[2];
    whole.step_collision_energy = sums[3];
    whole.step_ghost_cell_energy = sums[4];
    const auto& clock = local_.resource<Clock>();
    if (sums[1] > 0.0)
      view.template write<RunControl>().fail(
          stranded_failure(clock.time, clock.step, static_cast<std::uint64_t>(sums[1]), dt_));
  }

  // The sums the every-step samplers asked for (srd_step_sums.hpp): of this
  // rank's own particles and cells, per fixed chunk of particles, added over
  // the chunks and then the ranks in order; so that the samplers need not
  // gather the particles every step.
  void fill_step_sums(View view) {
    if (!view.template has<SrdStepSums<D>>()) return;
    auto& sums = view.template write<SrdStepSums<D>>();
    if (sums.layer_requests.empty() && !sums.stress_requested) return;
    const auto& cells = local_.resource<SrdCells<D>>();
    const Columns c = columns();
    const std::uint8_t* copy = local_.component<DomainGhost>().data();
    constexpr std::size_t w = 3 + D;
    std::vector<std::size_t> at;  // where each request's rows start
    std::size_t width = 0;
    for (const LayerSumsRequest& r : sums.layer_requests) {
      at.push_back(width);
      width += static_cast<std::size_t>(r.layers) * w;
    }
    const std::size_t stress_at = width;
    if (sums.stress_requested) width += 3;
    constexpr std::size_t chunk = 16384;
    const std::size_t n = local_.size(), chunks = (n + chunk - 1) / chunk;
    std::vector<double> partial(chunks * width, 0.0);
    const double half = 0.5 * cells.length[1 % D];
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
      double* out = partial.data() + k * width;
      for (std::size_t i = k * chunk; i < std::min(n, (k + 1) * chunk); ++i) {
        if (copy[i]) continue;
        const Vec<D>& v = c.v[i];
        for (std::size_t q = 0; q < at.size(); ++q) {
          const LayerSumsRequest& r = sums.layer_requests[q];
          const int layer = std::clamp(static_cast<int>(std::floor(c.x[i][r.axis])), 0, r.layers - 1);
          double* row = out + at[q] + static_cast<std::size_t>(layer) * w;
          row[0] += 1.0;
          row[1] += v[r.flow];
          row[2] += v.squaredNorm();
          for (int a = 0; a < D; ++a) row[3 + a] += v[a];
        }
        if (sums.stress_requested && D >= 2) {
          out[stress_at] += v[0] * v[1 % D];
          out[stress_at + 1] += v[1 % D] * (c.x[i][1 % D] - half);
          out[stress_at + 2] += v[1 % D] * v[1 % D];
        }
      }
    });
    std::vector<double> mine(width + 1, 0.0);
    for (std::size_t k = 0; k < chunks; ++k)
      for (std::size_t j = 0; j < width; ++j) mine[j] += partial[k * width + j];
    if (sums.stress_requested)
      for (std::size_t cell = 0; cell < cells.cell_count(); ++cell)
        if (cells.owns(cell)) mine[width] += cells.transfer[cell];
    communicating([&] { mine = ranks_.add_across(mine); });
    sums.layers.assign(at.size(), {});
    for (std::size_t q = 0; q < at.size(); ++q) {
      const auto rows = static_cast<std::ptrdiff_t>(sums.layer_requests[q].layers * static_cast<int>(w));
      sums.layers[q].assign(mine.begin() + static_cast<std::ptrdiff_t>(at[q]), mine.begin() + static_cast<std::ptrdiff_t>(at[q]) + rows);
    }
    if (sums.stress_requested) {
      for (std::size_t k = 0; k < 3; ++k) sums.stress[k] = mine[stress_at + k];
      sums.transfer = mine[width];
    }
    sums.step = local_.resource<Clock>().step;
  }

  // The ghosts that came with the migrants, and the copies this rank kept.
  void add_ghosts() {
    append(arrived_ghosts_, 1);
    append(kept_, 1);
  }

  static constexpr const char* axis_names[3] = {"x", "y", "z"};
  const Communicator& ranks_;
  int axis_;
  DomainStepPhysics<D> physics_;
  SlabDomain slab_;
  double length_;  // of the periodic box along the slab axis
  double length_x_;
  double low_, high_;  // this rank's slab
  std::size_t world_size_ = 0;  // the World's, while it holds this rank's part
  Totals own_totals_;           // this rank's cells', meanwhile
  double ghost_below_edge_ = 0.0, ghost_above_edge_ = 0.0;  // this step's: particles below / above go as ghosts
  double keep_below_edge_ = 0.0, keep_above_edge_ = 0.0;    // this step's: leavers beyond them stay as ghosts
  World local_;
  double dt_;
  SrdGridShift<D> shift_;
  SrdCellBinning<D> binning_;
  SrdRotation<D> rotation_;
  bool ids_ = false;
  bool images_ = false;
  std::uint64_t reorder_interval_;
  bool scattered_ = false;
  bool stepped_ = false;  // the slabs' cells have been reduced (else the initial state's are the World's)
  unsigned periodic_ = 0;  // bit a: axis a of the whole box wraps
  bool accounts_ = false;  // walls or the energy ledger: per-step sums over the ranks
  mutable bool clamping_reported_ = false;
  DomainBalance balance_;
  Shear shear_;  // this step's, for packing: read per particle, not looked up in local_ each time
  bool host_current_ = true;
  std::vector<double> to_below_, to_above_;  // this round's ghosts for the neighbours, packed
  std::vector<double> up_, down_;            // this round's migrants, packed
  std::vector<std::size_t> gone_;            // this round's leavers, to remove
  Communicator::Exchange exchange_;          // the first round, in flight
  Communicator::Sum agreement_;              // on two ranks: the signal, in flight until the step ends
  bool agreement_open_ = false;
  std::vector<double> arrived_ghosts_, kept_;  // this step's ghosts: the neighbours' and this rank's copies
  std::vector<SortedOut> sorted_out_;
  PhaseTimes<12> times_{{"streaming", "migration", "ghost_exchange", "binning", "reduction", "rotation",
                         "ghost_removal", "gather", "communication", "agreement", "balance_check", "rebalance"}};
};

}  // namespace granflow::srd
