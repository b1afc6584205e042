#pragma once
// The soft-sphere step of one system spread over the ranks of an MPI job
// (`mpirun -np K granflow run`). The neighbour lists' cells come in layers
// along z (neighbour_list.hpp), each at least one interaction range (two
// radii and the skin) high; rank r owns the spheres of a slab of whole
// layers (slab_domain.hpp) and holds copies of the layer just below and
// just above it: every sphere within reach of one of its own. Per step:
//
//  - velocity Verlet's half kick and drift of every sphere the rank holds;
//  - the ranks agree whether some sphere moved half the skin since the
//    last build, and on a signal, in one gather, which also adds the last
//    step's energy terms over the ranks (the one synchronisation a step);
//  - if not, each rank sends the positions and velocities of its lowest
//    and highest layer to the neighbours whose copies they are;
//  - if so: the watchdog's check of every position, then the spheres that
//    left the slab go to their new owner (and, every balance.every_steps,
//    the slabs move so that each holds about as many spheres), the copies
//    of the edge layers are sent anew, and the lists are built over the
//    spheres the rank holds;
//  - the contact forces and the second half kick; the energy terms of the
//    step are summed per layer, and added over the layers in their order
//    at the next step's gather, or at the next gather of the whole system.
//
// A fresh bed starts from the part each rank made (bed_by_part.hpp): the
// slabs are settled by sphere count, and the first lists and forces are
// built over the ranks as a build does; a resumed run starts from the rows
// of the layers each rank holds, which it read of the checkpoint
// (resumed_part.hpp); a stored start scatters the whole every rank read.
//
// Every sphere's force is summed as on one rank, bit for bit: a rank holds
// its spheres in the whole system's cell order (each carries its index in
// the whole system at the last build, which orders the spheres of a cell at
// the next), so its lists of the layers it owns, and of the layer below,
// are the whole system's, pair for pair and in order; the force pass takes
// the layers of one parity at a time as on one rank; the tangential
// springs' history travels with the first sphere of each pair, keyed by the
// two spheres' ids. The pairs across a slab boundary are evaluated by both
// ranks, each keeping the force on its own sphere (no reverse
// communication). The result does not depend on the number of ranks, the
// slab bounds or the threads; a run resumes bit for bit on any number of
// ranks.
//
// Observers run on every rank over its own spheres: lend_part puts them
// into the World, in the whole system's order, and the observers total
// their sums over the ranks in the whole's own grouping (ObservedPart::sums),
// so that they too are one rank's bit for bit. A sphere's side of a divider
// (CompartmentSide) travels with it. No rank then holds the whole system.
// A checkpoint is written from the same lent parts, each rank's rows in
// rank order (write_checkpoint_by_rank), with each rank's own spheres'
// lists in the whole system's numbering (lend_checkpoint_state): the file
// is that of one rank and resumes on any number of ranks. An observer that
// cannot run by rank reads the whole on rank 0: synchronise_host gathers
// every rank's spheres into it, in rank order, with the neighbour lists;
// rank 0 observes alone and shares its decisions (Run::run_observers), and
// lets the whole go at the next step.

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "components/angular_velocity.hpp"
#include "components/box.hpp"
#include "components/clock.hpp"
#include "components/compartment_side.hpp"
#include "components/force.hpp"
#include "components/image_count.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/core/communicator.hpp"
#include "engine/core/observed_part.hpp"
#include "engine/core/phase_times.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/dem/bed_by_part.hpp"
#include "systems/dem/contact_forces.hpp"
#include "systems/dem/dem_domain_gather.hpp"
#include "systems/dem/dem_energy.hpp"
#include "systems/dem/dem_watchdog.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/velocity_verlet.hpp"
#include "systems/geometry/cell_grid.hpp"
#include "systems/geometry/counting_sort.hpp"
#include "systems/geometry/slab_domain.hpp"

namespace granflow::dem {

inline const SystemDescription dem_domain_step_description{
    "dem_domain_step",
    "the soft-sphere step over MPI ranks: slabs of neighbour-list layers along z, copies of the edge layers, "
    "migration at list builds"};

// When the slabs are rebalanced: at the start and at the first list build
// after every `every_steps` steps (0: never), where the busiest rank's load
// (two per sphere, one per listed pair) exceeds `threshold` times the mean.
struct DemDomainBalance {
  std::int64_t every_steps = 0;
  double threshold = 1.1;
};

using DemDomainStepBase =
    SystemOf<Reads<Box<3>, DemWatch<3>, BedByPart, ResumedPart>,
             Writes<EveryColumn, Clock, NeighbourList<3>, DemInteractions<3>, DemLedger, RunControl>>;

class DemDomainStep : public DemDomainStepBase {
 public:
  // `layers`: the whole system's list cells (list_cells of its box, range
  // and sphere count), whose layers along z the slabs are made of.
  DemDomainStep(const Communicator& ranks, double dt, const CellGrid<3>& layers, DemDomainBalance balance)
      : ranks_(ranks),
        dt_(dt),
        grid_(layers),
        slab_(ranks.rank(), ranks.size(), layers.cells(2), "z", domain_layers_from),
        balance_(balance),
        kick_drift_(dt),
        kick_(dt) {
    local_.emplace_resource<Clock>();
  }

  std::string name() const override { return "dem_domain_step"; }

  void run_on(View view) override {
    if (!scattered_) start(view);
    // A whole that a round gathered onto rank 0 is stale once the step moves on.
    else if (view.size() > 0) release_whole(view);
    times_.timed(0, [&] { kick_drift_.run(local_); });
    view.template write<Clock>() = local_.resource<Clock>();
    // The drift moved the rank's own spheres only (move_own_only) and
    // measured how far they went since the build.
    const auto& nl = local_.resource<NeighbourList<3>>();
    const double moved = nl.displacement_step == local_.resource<Clock>().step ? nl.displacement_squared
                                                                                : largest_owned_displacement();
    // One gather a step: whether the rank must build, its signal, and the
    // last step's energy terms.
    std::vector<double> mine{!(moved <= 0.25 * nl.skin * nl.skin) ? 1.0 : 0.0, ranks_.interrupted_here() ? 1.0 : 0.0};
    const bool booking = pending_valid_;
    if (booking) mine.insert(mine.end(), pending_.begin(), pending_.end());
    std::vector<double> all;
    times_.timed(1, [&] { all = ranks_.gather_all(mine); });
    bool build = false, interrupted = false;
    std::vector<double> terms;
    for (std::size_t r = 0, at = 0; r < static_cast<std::size_t>(slab_.ranks); ++r) {
      build |= all[at] != 0.0;
      interrupted |= all[at + 1] != 0.0;
      const std::size_t length = booking ? energy_width() * static_cast<std::size_t>(slab_.bounds[r + 1] - slab_.bounds[r]) : 0;
      terms.insert(terms.end(), all.begin() + static_cast<std::ptrdiff_t>(at + 2),
                   all.begin() + static_cast<std::ptrdiff_t>(at + 2 + length));
      at += 2 + length;
    }
    ranks_.agree_on_interrupt(interrupted);
    if (booking) book_energy_terms(view, terms);
    if (build) {
      if (!rebuild(view)) return;
    } else {
      times_.timed(5, [&] { refresh_copies(); });
    }
    times_.timed(6, [&] { forces_.run(local_); });
    times_.timed(7, [&] { keep_energy_terms(); });
    times_.timed(8, [&] { kick_.run(local_); });
    host_current_ = false;
  }

  // Every rank's spheres into the whole World, in the whole system's order,
  // with the lists as one rank would hold them.
  void synchronise_host(World& whole) override {
    // A World that holds this rank's part of a fresh bed is no whole yet.
    if (!scattered_ && View(whole).has<BedByPart>()) start(View(whole));
    book_pending_energy_terms(View(whole));
    if (host_current_ || !scattered_) return;
    times_.timed(9, [&] { gather_whole(ranks_, local_, below_, owned_, grid_, whole); });
    host_current_ = true;
  }

  // This rank's own spheres, in the whole system's order, lent to the
  // World for observers that run by rank (ObservedPart, whose sums take the
  // whole's grouping: the same bits as one rank): the World's columns are
  // set aside until take_back_part. The last step's energy terms are
  // booked first, as synchronise_host books them for the whole.
  bool lend_part(World& world) override {
    if (!scattered_) start(View(world));
    std::size_t lendable = 0;
    for_each_column([&](auto column, auto&) {
      lendable += world.has_component<typename decltype(column)::type>() ? 1 : 0;
    });
    // Every rank decides alike, or some would gather while others lend.
    if (ranks_.least_across({lendable == world.column_count() ? 1.0 : 0.0}).front() == 0.0) return false;
    book_pending_energy_terms(View(world));
    lent_from_size_ = world.size();
    for_each_column([&](auto column, auto& stash) {
      using C = typename decltype(column)::type;
      if (!world.has_component<C>()) return;
      auto& values = world.component<C>().values;
      stash.swap(values);
      const auto& own = local_.component<C>().values;
      values.assign(own.begin() + static_cast<std::ptrdiff_t>(below_),
                    own.begin() + static_cast<std::ptrdiff_t>(below_ + owned_));
    });
    world.resize(owned_);
    world.emplace_resource<ObservedPart>(ranks_, 2, slab_.low(), slab_.high(), first_own_index_);
    return true;
  }
  // A checkpoint carries the lists as one rank's, in the whole system's
  // order: each rank gives its own spheres', as rows that follow one another.
  void lend_checkpoint_state(World& world) override {
    lend_lists_of_part(ranks_, local_, below_, owned_, grid_, world.resource<NeighbourList<3>>());
  }
  void take_back_part(World& world) override {
    if (auto& lists = world.resource<NeighbourList<3>>(); lists.part_of_whole) lists.release();
    // What an observer keeps per sphere goes back with it.
    if (sides_ && world.has_component<CompartmentSide>()) {
      const auto& kept = world.component<CompartmentSide>().values;
      std::copy(kept.begin(), kept.end(),
                local_.component<CompartmentSide>().values.begin() + static_cast<std::ptrdiff_t>(below_));
    }
    for_each_column([&](auto column, auto& stash) {
      using C = typename decltype(column)::type;
      if (world.has_component<C>()) world.component<C>().values.swap(stash);
    });
    world.resize(lent_from_size_);
  }

  std::vector<ProfileEntry> device_profile() const override { return times_.entries("dem_domain_step", ranks_); }

 private:
  // A sphere packed for another rank: its whole index, id, mass, radius,
  // position and velocity, images, spin and wall springs, and its side of a
  // divider where the run has them, then its pairs' springs (partner id and
  // shear each).
  std::size_t fixed_width() const {
    return 10 + (images_ ? 3 : 0) + (rotating_ ? 3 + 3 * walls_ : 0) + (sides_ ? 1 : 0);
  }

  // Each column the step holds, with the place a lent World's own column
  // waits in meanwhile.
  template <class Visit>
  void for_each_column(Visit&& visit) {
    visit(std::type_identity<Position<3>>{}, lent_.x);
    visit(std::type_identity<Velocity<3>>{}, lent_.v);
    visit(std::type_identity<Force<3>>{}, lent_.f);
    visit(std::type_identity<Mass>{}, lent_.mass);
    visit(std::type_identity<Radius>{}, lent_.radius);
    visit(std::type_identity<ParticleId>{}, lent_.id);
    visit(std::type_identity<ImageCount<3>>{}, lent_.image);
    visit(std::type_identity<AngularVelocity>{}, lent_.omega);
    visit(std::type_identity<Torque>{}, lent_.torque);
    visit(std::type_identity<CompartmentSide>{}, lent_.side);
  }

  // ---- the start: this rank's part of the system -------------------------

  // From the rank's part of a fresh bed (bed_by_part.hpp), or else from the
  // whole system that every rank holds (a resumed run, a stored start).
  void start(View view) {
    if (view.template has<BedByPart>()) start_from_part(view);
    else scatter(view);
  }

  // What the local World takes from the run's, whatever it holds: the
  // optional columns, the box, the contacts, the lists' settings, the
  // clock; and whether all masses and all radii are equal over the ranks.
  void take_settings(View view) {
    const auto& settings = view.template read<NeighbourList<3>>();
    images_ = view.template has<ImageCount<3>>();
    rotating_ = view.template has<AngularVelocity>();
    sides_ = view.template has<CompartmentSide>();
    walls_ = settings.walls;
    constexpr double inf = std::numeric_limits<double>::infinity();
    // The least mass and radius and, negated, the largest, over the ranks.
    std::vector<double> extremes{inf, inf, inf, inf};
    for (const double m : view.template read<Mass>().values) {
      extremes[0] = std::min(extremes[0], m);
      extremes[1] = std::min(extremes[1], -m);
    }
    for (const double r : view.template read<Radius>().values) {
      extremes[2] = std::min(extremes[2], r);
      extremes[3] = std::min(extremes[3], -r);
    }
    extremes = ranks_.least_across(extremes);
    alike_ = {extremes[0] == -extremes[1], extremes[2] == -extremes[3]};
    local_.resource<Clock>() = view.template read<Clock>();
    last_balance_ = local_.resource<Clock>().step;
    local_.emplace_resource<Box<3>>(view.template read<Box<3>>());
    local_.emplace_resource<DemInteractions<3>>(view.template read<DemInteractions<3>>());
    auto& nl = local_.emplace_resource<NeighbourList<3>>();
    nl.skin = settings.skin;
    nl.reorder = true;
    nl.keeps_history = settings.keeps_history;
    nl.walls = settings.walls;
    nl.builds = settings.builds;
    add_columns();
  }

  // A fresh bed made by parts: the World holds the spheres this rank made,
  // in the order of their ids, which is the whole system's order before its
  // first build. The slabs are settled by sphere count as the bed was
  // split, a sphere another rank owns is passed on, and the lists and the
  // first forces are built over the ranks as one rank builds them over the
  // whole at its start (the spheres in cell order, the springs at rest).
  void start_from_part(View view) {
    take_settings(view);
    // The part moves into the local World, not copied: it is the rank's
    // largest holding at the start.
    const std::size_t n = view.size();
    for_each_column([&](auto column, auto&) {
      using C = typename decltype(column)::type;
      if (local_.has_component<C>()) std::swap(local_.component<C>().values, view.template write<C>().values);
    });
    local_.resize(n);
    const DomainColumns c = columns_of(local_, images_, rotating_, true);
    for (std::size_t i = 0; i < n; ++i) c.index[i] = static_cast<double>(c.id[i]);
    auto& nl = local_.resource<NeighbourList<3>>();
    nl.wall_shear.assign(rotating_ ? n * walls_ : 0, Shear{});
    std::vector<double> per_layer(static_cast<std::size_t>(slab_.cells), 0.0);
    for (std::size_t i = 0; i < n; ++i) per_layer[layer_of(c.x[i])] += 1.0;
    per_layer = ranks_.add_across(per_layer);
    if (const auto bounds = SlabDomain::balanced(per_layer, slab_.ranks);
        balance_.every_steps > 0 && bounds != slab_.bounds) {
      slab_.bounds = bounds;
      spdlog::info("step {}: the slabs now start at layers [{}] of {} (by sphere count)", local_.resource<Clock>().step,
                   fmt::join(slab_.bounds.begin(), slab_.bounds.end() - 1, ", "), slab_.cells);
    }
    below_ = 0;
    owned_ = n;
    was_.assign(n, none);
    arrived_.clear();
    previous_ = {};
    std::vector<std::uint32_t> own = migrate();
    const auto& index = local_.component<WholeIndex>();
    std::sort(own.begin(), own.end(), [&](std::uint32_t a, std::uint32_t b) { return index[a] < index[b]; });
    first_layer_ = held_layers().first;
    add_copies(own);
    build(view);
    forces_.run(local_);
    keep_energy_terms();
    // The first forces' terms, as one rank's start leaves them: no step to book yet.
    book_energy_terms(view, ranks_.gather_all(pending_), false);
    const auto& in = view.template read<DemInteractions<3>>();
    auto& ledger = view.template write<DemLedger>();
    ledger.last_wall_power = in.wall_power;
    ledger.last_dissipation_power = in.dissipation_power;
    scattered_ = true;
    host_current_ = false;
    release_whole(view);
  }

  // The whole system that every rank read (a stored start), or the rows of
  // the layers this rank holds that a resumed run read (ResumedPart, with
  // the lists in the whole system's numbering): the same spheres and lists.
  void scatter(View view) {
    const auto& whole_nl = view.template read<NeighbourList<3>>();
    const ResumedPart* part = view.template has<ResumedPart>() ? &view.template read<ResumedPart>() : nullptr;
    const std::size_t layers = static_cast<std::size_t>(grid_.cells(2));
    if ((part ? !whole_nl.part_of_whole : !whole_nl.built()) || whole_nl.slabs.size() != layers + 1 ||
        !whole_nl.reorder)
      throw std::logic_error("the soft-sphere step over ranks needs the whole system's lists built in cell order");
    take_settings(view);
    if (part) {
      if (part->bounds != slab_.bounds)
        spdlog::info("step {}: the slabs now start at layers [{}] of {} (two per sphere, one per pair)",
                     local_.resource<Clock>().step, fmt::join(part->bounds.begin(), part->bounds.end() - 1, ", "),
                     slab_.cells);
      slab_.bounds = part->bounds;
    } else if (balance_.every_steps > 0) {
      std::vector<double> per_layer(layers);
      for (std::size_t s = 0; s < layers; ++s)
        per_layer[s] = layer_load(whole_nl.slabs[s + 1] - whole_nl.slabs[s],
                                  whole_nl.offsets[whole_nl.slabs[s + 1]] - whole_nl.offsets[whole_nl.slabs[s]]);
      move_bounds_if_uneven(per_layer);
    }
    auto& nl = local_.resource<NeighbourList<3>>();
    const auto [first, end] = held_layers();
    const std::uint32_t base = whole_nl.slabs[first], count = whole_nl.slabs[end] - base;
    if (part && (part->first != base || part->count != count))
      throw std::logic_error("the resumed part is not the layers this rank holds");
    // Where the held spheres start in the World and its lists.
    const std::uint32_t from = part ? 0 : base;
    below_ = whole_nl.slabs[slab_.low()] - base;
    first_own_index_ = whole_nl.slabs[slab_.low()];
    owned_ = whole_nl.slabs[slab_.high()] - whole_nl.slabs[slab_.low()];
    local_.resize(count);
    auto& x = local_.component<Position<3>>();
    auto& v = local_.component<Velocity<3>>();
    auto& f = local_.component<Force<3>>();
    auto& id = local_.component<ParticleId>();
    auto& index = local_.component<WholeIndex>();
    const auto& mass = view.template read<Mass>();
    const auto& radius = view.template read<Radius>();
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t i = from + k;
      x[k] = view.template read<Position<3>>()[i];
      v[k] = view.template read<Velocity<3>>()[i];
      f[k] = view.template read<Force<3>>()[i];
      id[k] = view.template read<ParticleId>()[i];
      index[k] = static_cast<double>(base + k);
      local_.component<Mass>()[k] = mass[i];
      local_.component<Radius>()[k] = radius[i];
      if (images_) local_.component<ImageCount<3>>()[k] = view.template read<ImageCount<3>>()[i];
      if (rotating_) {
        local_.component<AngularVelocity>()[k] = view.template read<AngularVelocity>()[i];
        local_.component<Torque>()[k] = view.template read<Torque>()[i];
      }
      if (sides_) local_.component<CompartmentSide>()[k] = view.template read<CompartmentSide>()[i];
    }
    // The lists of the layers below the top one held: the whole system's,
    // whose partners all lie in the layers held; the top layer's own reach
    // into the next, which this rank does not hold, and are left empty.
    const std::uint32_t listed_end = whole_nl.slabs[std::min<std::size_t>(end, slab_.high())] - base;
    nl.order.resize(count);
    std::iota(nl.order.begin(), nl.order.end(), 0u);
    nl.offsets.assign(count + 1, 0);
    nl.list.clear();
    nl.shear.clear();
    for (std::uint32_t m = 0; m < count; ++m) {
      if (m < listed_end) {
        for (std::uint32_t p = whole_nl.offsets[from + m]; p < whole_nl.offsets[from + m + 1]; ++p) {
          nl.list.push_back(whole_nl.list[p] - base);
          if (nl.keeps_history) nl.shear.push_back(whole_nl.shear[p]);
        }
      }
      nl.offsets[m + 1] = static_cast<std::uint32_t>(nl.list.size());
    }
    nl.slabs.clear();
    for (std::size_t s = first; s <= end; ++s) nl.slabs.push_back(whole_nl.slabs[s] - base);
    nl.periodic_slabs = false;
    nl.reference.assign(whole_nl.reference.begin() + from, whole_nl.reference.begin() + from + count);
    if (nl.keeps_history)
      nl.wall_shear.assign(whole_nl.wall_shear.begin() + static_cast<std::ptrdiff_t>(from * walls_),
                           whole_nl.wall_shear.begin() + static_cast<std::ptrdiff_t>((from + count) * walls_));
    nl.derive();
    first_layer_ = first;
    move_own_only(nl);
    forces_.as_part_of_whole(first_layer_, alike_[0], alike_[1]);
    count_edges();
    scattered_ = true;
    // No rank needs the whole any more: observers run by rank, and a round
    // that cannot gathers it onto rank 0 again.
    release_whole(view);
  }
  static void release_whole(View view) {
    view.release();
    view.template write<NeighbourList<3>>().release();
  }

  void add_columns() {
    local_.add_component<Position<3>>();
    local_.add_component<Velocity<3>>();
    local_.add_component<Force<3>>();
    local_.add_component<Mass>();
    local_.add_component<Radius>();
    local_.add_component<ParticleId>();
    local_.add_component<WholeIndex>();
    if (images_) local_.add_component<ImageCount<3>>();
    if (rotating_) {
      local_.add_component<AngularVelocity>();
      local_.add_component<Torque>();
    }
    if (sides_) local_.add_component<CompartmentSide>();
  }

  // The layers this rank holds: its slab and the layer either side of it
  // (z is closed: none below the first slab, none above the last).
  std::pair<std::size_t, std::size_t> held_layers() const {
    const auto low = static_cast<std::size_t>(slab_.low()), high = static_cast<std::size_t>(slab_.high());
    return {low > 0 ? low - 1 : low, high < static_cast<std::size_t>(slab_.cells) ? high + 1 : high};
  }
  // The kicks and the drift go through the spheres of the lists' thread
  // domains: those are cut to the rank's own, so that the copies (which
  // the neighbours' next message sets) cost nothing and the drift measures
  // the own spheres' displacement alone, as the build test needs.
  void move_own_only(NeighbourList<3>& nl) const {
    for (auto& s : nl.domains.sphere)
      s = std::clamp(s, static_cast<std::uint32_t>(below_), static_cast<std::uint32_t>(below_ + owned_));
  }
  bool has_below() const { return slab_.rank > 0; }
  bool has_above() const { return slab_.rank + 1 < slab_.ranks; }

  std::size_t layer_of(const Vec<3>& x) const { return grid_.cell_of(x) / grid_.stride(2); }

  // How many of its own spheres in its lowest and highest layer (the
  // neighbours' copies) the rank sends each step.
  void count_edges() {
    const auto& nl = local_.resource<NeighbourList<3>>();
    const std::size_t low = static_cast<std::size_t>(slab_.low()) - first_layer_;
    const std::size_t high = static_cast<std::size_t>(slab_.high()) - 1 - first_layer_;
    send_low_ = has_below() ? nl.slabs[low + 1] - nl.slabs[low] : 0;
    send_high_ = has_above() ? nl.slabs[high + 1] - nl.slabs[high] : 0;
  }

  // A layer's share of the step: two per sphere and one per listed pair, as
  // the threads' domains weigh them (thread_domains.hpp).
  static double layer_load(std::size_t spheres, std::size_t pairs) {
    return 2.0 * static_cast<double>(spheres) + static_cast<double>(pairs);
  }

  void move_bounds_if_uneven(const std::vector<double>& per_layer) {
    if (!SlabDomain::uneven(per_layer, slab_.bounds, balance_.threshold)) return;
    const std::vector<double> loads = SlabDomain::loads(per_layer, slab_.bounds);
    const double total = std::accumulate(loads.begin(), loads.end(), 0.0);
    const double busiest = *std::max_element(loads.begin(), loads.end());
    const auto bounds = SlabDomain::balanced(per_layer, slab_.ranks);
    if (bounds == slab_.bounds) return;
    slab_.bounds = bounds;
    spdlog::info("step {}: the slabs now start at layers [{}] of {} (the busiest rank's load was {:.0f}, the mean "
                 "{:.0f}: two per sphere, one per pair)",
                 local_.resource<Clock>().step, fmt::join(bounds.begin(), bounds.end() - 1, ", "), slab_.cells, busiest,
                 total / static_cast<double>(slab_.ranks));
  }

  // ---- every step --------------------------------------------------------

  double largest_owned_displacement() const {
    const auto& x = local_.component<Position<3>>();
    const auto& nl = local_.resource<NeighbourList<3>>();
    const auto& box = local_.resource<Box<3>>();
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(below_, below_ + owned_, 4096), 0.0,
        [&](const auto& r, double most) {
          const double here = largest_displacement_squared(x.values.data(), nl, box, r.begin(), r.end());
          return here <= most ? most : here;  // NaN wins
        },
        [](double a, double b) { return b <= a ? a : b; });
  }

  // The neighbours' copies of this rank's edge layers, moved on a step.
  void refresh_copies() {
    const std::size_t width = rotating_ ? 9 : 6;
    const DomainColumns c = columns_of(local_, images_, rotating_, true);
    const auto pack_moved = [&](std::size_t from, std::size_t count) {
      std::vector<double> out;
      out.reserve(count * width);
      for (std::size_t i = from; i < from + count; ++i) {
        out.insert(out.end(), c.x[i].data(), c.x[i].data() + 3);
        out.insert(out.end(), c.v[i].data(), c.v[i].data() + 3);
        if (c.omega) out.insert(out.end(), c.omega[i].data(), c.omega[i].data() + 3);
      }
      return out;
    };
    const auto received = ranks_.exchange_with_neighbours(slab_.below(), pack_moved(below_, send_low_), slab_.above(),
                                                          pack_moved(below_ + owned_ - send_high_, send_high_), 0);
    if (received.from_below.size() != below_ * width ||
        received.from_above.size() != (local_.size() - below_ - owned_) * width)
      throw std::logic_error("the neighbours sent copies of another size than their layers at the last build");
    const auto unpack_moved = [&](const std::vector<double>& in, std::size_t from) {
      for (std::size_t k = 0; k * width < in.size(); ++k) {
        const double* p = in.data() + k * width;
        c.x[from + k] = Vec<3>(p[0], p[1], p[2]);
        c.v[from + k] = Vec<3>(p[3], p[4], p[5]);
        if (c.omega) c.omega[from + k] = Vec<3>(p[6], p[7], p[8]);
      }
    };
    unpack_moved(received.from_below, 0);
    unpack_moved(received.from_above, below_ + owned_);
  }

  // The values one layer adds to the step's energy terms: the pairs'
  // sums, then each wall's.
  std::size_t energy_width() const {
    return DemContactForces<3>::pair_sums + DemContactForces<3>::wall_sums * walls_;
  }

  // The force pass's sums of the rank's own layers, kept until the next
  // step's gather adds them over the ranks (or the next gather of the whole
  // system, where observers read them first), so that a step synchronises
  // the ranks once.
  void keep_energy_terms() {
    constexpr std::size_t P = DemContactForces<3>::pair_sums, W = DemContactForces<3>::wall_sums;
    const auto& pairs = forces_.pair_slab_sums();
    const auto& walls = forces_.wall_slab_sums();
    pending_.clear();
    for (auto layer = static_cast<std::size_t>(slab_.low()); layer < static_cast<std::size_t>(slab_.high()); ++layer) {
      const std::size_t s = layer - first_layer_;
      pending_.insert(pending_.end(), pairs.begin() + static_cast<std::ptrdiff_t>(P * s),
                      pairs.begin() + static_cast<std::ptrdiff_t>(P * (s + 1)));
      for (std::size_t w = 0; w < walls_; ++w)
        pending_.insert(pending_.end(), walls[w].begin() + static_cast<std::ptrdiff_t>(W * s),
                        walls[w].begin() + static_cast<std::ptrdiff_t>(W * (s + 1)));
    }
    pending_valid_ = true;
  }

  // The last force pass's terms, kept for the next step's gather, booked
  // now for a round that reads them (a gather of the whole, observers by rank).
  void book_pending_energy_terms(View view) {
    if (!pending_valid_) return;
    std::vector<double> all;
    times_.timed(10, [&] { all = ranks_.gather_all(pending_); });
    book_energy_terms(view, all);
  }

  // Every layer's sums, in layer order, into the whole system's energy
  // terms (added over the layers as one rank adds its slabs), and, where
  // `book`, that step's trapezoid into the ledger.
  void book_energy_terms(View view, const std::vector<double>& all, bool book = true) {
    constexpr std::size_t P = DemContactForces<3>::pair_sums, W = DemContactForces<3>::wall_sums;
    const std::size_t per_layer = energy_width();
    const std::size_t layers = all.size() / per_layer;
    std::vector<double> pair_partial(P * layers);
    std::vector<std::vector<double>> wall_partial(walls_, std::vector<double>(W * layers));
    for (std::size_t s = 0; s < layers; ++s) {
      const double* at = all.data() + s * per_layer;
      std::copy(at, at + P, pair_partial.begin() + static_cast<std::ptrdiff_t>(P * s));
      for (std::size_t w = 0; w < walls_; ++w)
        std::copy(at + P + W * w, at + P + W * (w + 1), wall_partial[w].begin() + static_cast<std::ptrdiff_t>(W * s));
    }
    auto& in = view.template write<DemInteractions<3>>();
    DemContactForces<3>::add_slab_sums(pair_partial, wall_partial, layers, in);
    if (book) view.template write<DemLedger>().book(dt_, in.wall_power, in.dissipation_power);
    pending_valid_ = false;
  }

  // ---- a list build ------------------------------------------------------
  //
  // The spheres stay in the local World: those that leave are packed for
  // their new owner, those that arrive are appended, and two permutations
  // (World::permute) put the rank's own in the whole system's cell order
  // and the copies of the neighbours' edge layers either side of them.

  // Returns false where a sphere escaped (the run then stops, exit 3).
  bool rebuild(View view) {
    if (escaped(view)) return false;
    auto& nl = local_.resource<NeighbourList<3>>();
    // The lists of the last build, whose own spheres' springs carry over.
    previous_.offsets.swap(nl.offsets);
    previous_.list.swap(nl.list);
    previous_.shear.swap(nl.shear);
    previous_ids_ = local_.component<ParticleId>().values;
    was_.assign(local_.size(), none);
    for (std::size_t i = below_; i < below_ + owned_; ++i) was_[i] = static_cast<std::uint32_t>(i);
    arrived_.clear();
    std::vector<std::uint32_t> own;
    times_.timed(2, [&] { own = migrate(); });
    first_layer_ = held_layers().first;
    times_.timed(3, [&] { add_copies(own); });
    times_.timed(4, [&] { build(view); });
    return true;
  }

  // The lists over the spheres now held, each numbered by its place in the
  // whole system's cell order.
  void build(View view) {
    std::int64_t before = 0;
    const std::vector<double> counts = ranks_.gather_all({static_cast<double>(owned_)});
    for (int r = 0; r < slab_.rank; ++r) before += static_cast<std::int64_t>(counts[static_cast<std::size_t>(r)]);
    first_own_index_ = static_cast<std::uint64_t>(before);
    auto& index = local_.component<WholeIndex>();
    for (std::size_t i = 0; i < local_.size(); ++i)
      index[i] = static_cast<double>(before) - static_cast<double>(below_) + static_cast<double>(i);
    build_lists();
    auto& nl = local_.resource<NeighbourList<3>>();
    ++nl.builds;
    view.template write<NeighbourList<3>>().builds = nl.builds;
    forces_.as_part_of_whole(first_layer_, alike_[0], alike_[1]);
    count_edges();
  }

  // The watchdog's check at a build: every rank learns the first escaped
  // sphere in the whole system's order and stops with the same diagnosis.
  bool escaped(View view) {
    const auto& watch = view.template read<DemWatch<3>>();
    const auto e = first_escaped<3>(local_.component<Position<3>>(), &local_.component<ParticleId>(), watch, below_,
                                    below_ + owned_);
    std::vector<double> mine;
    if (e) mine = {static_cast<double>(e->sphere), static_cast<double>(e->axis), e->position};
    const std::vector<double> all = ranks_.gather_all(mine);
    if (all.empty()) return false;
    fail_run<3>(view, escape_diagnosis<3>({static_cast<std::uint64_t>(all[0]), static_cast<int>(all[1]), all[2]}, watch));
    return true;
  }

  static constexpr std::uint32_t none = ~std::uint32_t{0};

  // Sphere i (of the local World's columns c) onto `out`: its whole index, id, mass, radius, position and
  // velocity, images, spin and wall springs, its side where the run has them, then
  // the springs of the pairs it is the first of (partner id and shear each),
  // from the last build's lists where the rank owned it, else as they came
  // with it.
  void pack(const DomainColumns& c, std::size_t i, std::vector<double>& out) const {
    out.push_back(c.index[i]);
    out.push_back(c.id[i]);
    out.push_back(c.mass[i]);
    out.push_back(c.radius[i]);
    out.insert(out.end(), c.x[i].data(), c.x[i].data() + 3);
    out.insert(out.end(), c.v[i].data(), c.v[i].data() + 3);
    if (c.image)
      for (int a = 0; a < 3; ++a) out.push_back(c.image[i][a]);
    if (c.omega) {
      out.insert(out.end(), c.omega[i].data(), c.omega[i].data() + 3);
      const auto& nl = local_.resource<NeighbourList<3>>();
      for (std::size_t wall = 0; wall < walls_; ++wall) {
        const Shear& h = nl.wall_shear[i * walls_ + wall];
        out.insert(out.end(), h.begin(), h.end());
      }
    }
    if (c.side) out.push_back(c.side[i]);
    const std::size_t count_at = out.size();
    out.push_back(0.0);
    const auto add = [&](std::uint32_t partner, const Shear& h) {
      out.push_back(partner);
      out.insert(out.end(), h.begin(), h.end());
      out[count_at] += 1.0;
    };
    if (was_[i] != none) {
      for (std::uint32_t q = previous_.offsets[was_[i]]; q < previous_.offsets[was_[i] + 1]; ++q)
        if (!previous_.shear.empty() && !is_untouched(previous_.shear[q])) add(previous_ids_[previous_.list[q]], previous_.shear[q]);
    } else if (const auto found = arrived_.find(c.id[i]); found != arrived_.end()) {
      for (const auto& [partner, h] : found->second) add(partner, h);
    }
  }

  // A spring that holds nothing: +0 in every component (a -0 one, from a
  // pair whose spheres swapped order, must travel to stay bit for bit).
  static bool is_untouched(const Shear& h) {
    return std::all_of(h.begin(), h.end(), [](double c) { return std::bit_cast<std::uint64_t>(c) == 0; });
  }

  // Where each packed sphere of a message starts.
  std::vector<std::size_t> starts_of(const std::vector<double>& in) const {
    std::vector<std::size_t> out;
    const std::size_t fixed = fixed_width();
    for (std::size_t at = 0; at < in.size(); at += fixed + 1 + 4 * static_cast<std::size_t>(in[at + fixed]))
      out.push_back(at);
    return out;
  }
  std::size_t layer_of_packed(const double* p) const { return layer_of(Vec<3>(p[4], p[5], p[6])); }

  // Packed spheres (each at in[at] for `at` in `starts`) appended to the
  // local World, their springs kept by id for the lists and for passing on.
  void append(const std::vector<double>& in, const std::vector<std::size_t>& starts) {
    const std::size_t first = local_.size();
    local_.resize(first + starts.size());
    auto& nl = local_.resource<NeighbourList<3>>();
    if (rotating_) nl.wall_shear.resize(local_.size() * walls_);
    was_.resize(local_.size(), none);
    const DomainColumns c = columns_of(local_, images_, rotating_, true);
    for (std::size_t k = 0; k < starts.size(); ++k) {
      const double* d = in.data() + starts[k];
      const std::size_t i = first + k;
      c.index[i] = d[0];
      c.id[i] = static_cast<std::uint32_t>(d[1]);
      c.mass[i] = d[2];
      c.radius[i] = d[3];
      c.x[i] = Vec<3>(d[4], d[5], d[6]);
      c.v[i] = Vec<3>(d[7], d[8], d[9]);
      std::size_t at = 10;
      if (c.image) {
        for (int a = 0; a < 3; ++a) c.image[i][a] = static_cast<std::int32_t>(d[at + static_cast<std::size_t>(a)]);
        at += 3;
      }
      if (c.omega) {
        c.omega[i] = Vec<3>(d[at], d[at + 1], d[at + 2]);
        at += 3;
        for (std::size_t wall = 0; wall < walls_; ++wall, at += 3)
          nl.wall_shear[i * walls_ + wall] = {d[at], d[at + 1], d[at + 2]};
      }
      if (c.side) c.side[i] = static_cast<std::uint8_t>(d[at++]);
      const auto count = static_cast<std::size_t>(d[at++]);
      if (count == 0) continue;
      auto& springs = arrived_[c.id[i]];
      springs.clear();
      for (std::size_t s = 0; s < count; ++s, at += 4)
        springs.push_back({static_cast<std::uint32_t>(d[at]), {d[at + 1], d[at + 2], d[at + 3]}});
    }
  }

  // Every column of the local World reordered (it has no listeners and
  // holds no other columns) through buffers kept from build to build: World::permute
  // would hand a large column's old storage back to the system each time
  // and fault the next one's in, which costs the build more than the copy.
  void permute_columns(const std::vector<std::uint32_t>& order) {
    const auto permute = [&](auto& values, auto& spare) {
      spare.resize(order.size());
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 1u << 14), [&](const auto& r) {
        for (std::size_t k = r.begin(); k != r.end(); ++k) spare[k] = values[order[k]];
      });
      values.swap(spare);
    };
    permute(local_.component<Position<3>>().values, spare_vectors_);
    permute(local_.component<Velocity<3>>().values, spare_vectors_);
    permute(local_.component<Force<3>>().values, spare_vectors_);
    permute(local_.component<Mass>().values, spare_reals_);
    permute(local_.component<Radius>().values, spare_reals_);
    permute(local_.component<WholeIndex>().values, spare_reals_);
    permute(local_.component<ParticleId>().values, spare_ids_);
    if (images_) permute(local_.component<ImageCount<3>>().values, spare_images_);
    if (rotating_) {
      permute(local_.component<AngularVelocity>().values, spare_vectors_);
      permute(local_.component<Torque>().values, spare_vectors_);
    }
    if (sides_) permute(local_.component<CompartmentSide>().values, spare_sides_);
  }

  // Reorders the local World (and what follows its spheres outside it):
  // sphere k becomes the one that was order[k]; then keeps the first `kept`.
  void reorder(const std::vector<std::uint32_t>& order, std::size_t kept) {
    permute_columns(order);
    auto& nl = local_.resource<NeighbourList<3>>();
    std::vector<std::uint32_t> was(order.size());
    std::vector<Shear> wall_shear(rotating_ ? order.size() * walls_ : 0);
    for (std::size_t k = 0; k < order.size(); ++k) {
      was[k] = was_[order[k]];
      for (std::size_t wall = 0; wall < (rotating_ ? walls_ : 0); ++wall)
        wall_shear[k * walls_ + wall] = nl.wall_shear[order[k] * walls_ + wall];
    }
    was_.swap(was);
    nl.wall_shear.swap(wall_shear);
    local_.resize(kept);
    was_.resize(kept);
    if (rotating_) nl.wall_shear.resize(kept * walls_);
  }

  // The own spheres that left the slab to the rank that owns them now, a
  // neighbour at a time until every sphere is home (one round, but where
  // the slabs moved), and (every balance.every_steps) the slabs moved to
  // even out the spheres. The arrivals are appended to the local World;
  // returns the rank's own spheres now, in the whole system's order as of
  // the last build.
  std::vector<std::uint32_t> migrate() {
    const std::int64_t step = local_.resource<Clock>().step;
    std::vector<std::size_t> layer(local_.size(), 0);
    const auto& x = local_.component<Position<3>>();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(below_, below_ + owned_, 4096), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) layer[i] = layer_of(x[i]);
    });
    if (balance_.every_steps > 0 && step - last_balance_ >= balance_.every_steps) {
      last_balance_ = step;
      // The spheres where they are now, their pairs where the last build
      // listed them (its lists of the own layers are whole).
      std::vector<double> per_layer(static_cast<std::size_t>(slab_.cells), 0.0);
      for (std::size_t i = below_; i < below_ + owned_; ++i) per_layer[layer[i]] += layer_load(1, 0);
      const auto& slabs = local_.resource<NeighbourList<3>>().slabs;
      for (auto layer_of_slab = static_cast<std::size_t>(slab_.low()); layer_of_slab < static_cast<std::size_t>(slab_.high());
           ++layer_of_slab) {
        const std::size_t k = layer_of_slab - first_layer_;
        per_layer[layer_of_slab] += layer_load(0, previous_.offsets[slabs[k + 1]] - previous_.offsets[slabs[k]]);
      }
      move_bounds_if_uneven(ranks_.add_across(per_layer));
    }
    std::vector<double> down, up;
    std::vector<std::uint32_t> staying;
    staying.reserve(owned_);
    const DomainColumns c = columns_of(local_, images_, rotating_, true);
    for (std::size_t i = below_; i < below_ + owned_; ++i) {
      const int owner = slab_.owner(static_cast<double>(layer[i]));
      if (owner == slab_.rank) staying.push_back(static_cast<std::uint32_t>(i));
      else pack(c, i, owner < slab_.rank ? down : up);
    }
    std::vector<double> arrived_below, arrived_above;
    for (;;) {
      const auto received = ranks_.exchange_with_neighbours(slab_.below(), down, slab_.above(), up, 2);
      down.clear();
      up.clear();
      std::int64_t travelling = 0;
      for (const bool from_below : {true, false}) {
        const auto& in = from_below ? received.from_below : received.from_above;
        for (const std::size_t at : starts_of(in)) {
          const std::size_t length = fixed_width() + 1 + 4 * static_cast<std::size_t>(in[at + fixed_width()]);
          const int owner = slab_.owner(static_cast<double>(layer_of_packed(in.data() + at)));
          auto& to = owner == slab_.rank ? (from_below ? arrived_below : arrived_above)
                                         : (owner < slab_.rank ? down : up);
          travelling += owner != slab_.rank;
          to.insert(to.end(), in.begin() + static_cast<std::ptrdiff_t>(at),
                    in.begin() + static_cast<std::ptrdiff_t>(at + length));
        }
      }
      if (ranks_.sum(travelling) == 0) break;
    }
    // Arrivals from below come before the rank's own in the whole system's
    // order, those from above after; one passed on over several ranks
    // arrives after those from nearer ones, so each side's go in by their
    // whole index.
    std::vector<std::uint32_t> own;
    own.reserve(staying.size() + 64);
    for (const auto* in : {&arrived_below, &arrived_above}) {
      std::vector<std::size_t> starts = starts_of(*in);
      std::sort(starts.begin(), starts.end(), [&](std::size_t a, std::size_t b) { return (*in)[a] < (*in)[b]; });
      const std::size_t first = local_.size();
      append(*in, starts);
      if (in == &arrived_above) own.insert(own.end(), staying.begin(), staying.end());
      for (std::size_t k = 0; k < starts.size(); ++k) own.push_back(static_cast<std::uint32_t>(first + k));
    }
    return own;
  }

  // The own spheres (`own`, in the whole system's order) in cell order, the
  // copies of their lowest and highest layer sent to the neighbours, and
  // theirs put either side; what the rank no longer holds is dropped. One
  // permutation of the local World.
  void add_copies(const std::vector<std::uint32_t>& own) {
    const std::size_t count = own.size();
    const auto& x = local_.component<Position<3>>();
    const std::size_t stride = grid_.stride(2);
    // Every own sphere lies in the slab: its cells alone are counted.
    const auto low = static_cast<std::size_t>(slab_.low()), high = static_cast<std::size_t>(slab_.high());
    const std::size_t cells = (high - low) * stride;
    std::vector<std::uint32_t> cell(count), start(cells + 1), members(count), scratch;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& r) {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
        cell[k] = static_cast<std::uint32_t>(grid_.cell_of(x[own[k]]) - low * stride);
    });
    count_scan_fill(cell.data(), count, cells, start.data(), members.data(), scratch);
    for (auto& m : members) m = own[m];
    std::vector<double> down, up;
    const DomainColumns c = columns_of(local_, images_, rotating_, true);
    if (has_below())
      for (std::uint32_t k = start[0]; k < start[stride]; ++k) pack(c, members[k], down);
    if (has_above())
      for (std::uint32_t k = start[cells - stride]; k < start[cells]; ++k) pack(c, members[k], up);
    const auto received = ranks_.exchange_with_neighbours(slab_.below(), down, slab_.above(), up, 1);
    const auto below_starts = starts_of(received.from_below), above_starts = starts_of(received.from_above);
    const auto below_at = static_cast<std::uint32_t>(local_.size());
    append(received.from_below, below_starts);
    const auto above_at = static_cast<std::uint32_t>(local_.size());
    append(received.from_above, above_starts);
    std::vector<std::uint32_t> order;
    order.reserve(local_.size());
    for (std::uint32_t i = below_at; i < above_at; ++i) order.push_back(i);
    order.insert(order.end(), members.begin(), members.end());
    for (auto i = above_at; i < static_cast<std::uint32_t>(local_.size()); ++i) order.push_back(i);
    const std::size_t kept = order.size();
    std::vector<bool> taken(local_.size(), false);
    for (const std::uint32_t i : order) taken[i] = true;
    for (std::size_t i = 0; i < local_.size(); ++i)
      if (!taken[i]) order.push_back(static_cast<std::uint32_t>(i));
    reorder(order, kept);
    below_ = below_starts.size();
    owned_ = count;
  }

  // The lists over the held spheres, as neighbour_list.hpp builds them, on
  // the cells of the layers held; each pair's spring is that of its two
  // spheres (negated where they swapped order) in the last build's lists
  // of the one this rank owned, or as it came with them.
  void build_lists() {
    auto& nl = local_.resource<NeighbourList<3>>();
    const auto& box = local_.resource<Box<3>>();
    const std::size_t n = local_.size();
    const std::size_t stride = grid_.stride(2);
    const std::size_t held = held_layers().second - first_layer_;
    const CellGrid<3> cells({}, box.length, {grid_.cells(0), grid_.cells(1), static_cast<int>(held)},
                            {box.periodic[0], box.periodic[1], false});
    std::vector<std::uint32_t> sorted_cell(n), start(cells.cell_count() + 1, 0);
    std::vector<std::array<double, 4>> sorted(n);
    const auto& x = local_.component<Position<3>>();
    const auto& radius = local_.component<Radius>();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
      for (std::size_t m = r.begin(); m != r.end(); ++m) {
        sorted_cell[m] = static_cast<std::uint32_t>(grid_.cell_of(x[m]) - first_layer_ * stride);
        for (int a = 0; a < 3; ++a) sorted[m][static_cast<std::size_t>(a)] = x[m][a];
        sorted[m][3] = radius[m];
      }
    });
    for (std::size_t m = 0; m < n; ++m) ++start[sorted_cell[m] + 1];
    for (std::size_t c = 0; c < cells.cell_count(); ++c) start[c + 1] += start[c];
    nl.order.resize(n);
    std::iota(nl.order.begin(), nl.order.end(), 0u);
    list_partners(cells, start, sorted_cell, sorted, box, nl);
    keep_pairs_of_own(nl);
    nl.slabs.resize(held + 1);
    for (std::size_t s = 0; s <= held; ++s) nl.slabs[s] = start[s * stride];
    nl.periodic_slabs = false;
    nl.derive();
    if (nl.keeps_history) carry_springs(nl);
    move_own_only(nl);
    nl.reference.assign(x.values.begin(), x.values.end());
    nl.displacement_step = -1;
  }

  // Only the pairs with a sphere of the rank's own: those of two copies
  // (in the layer below, and all of the layer above, whose lists miss the
  // layer beyond) give forces to copies only. The pairs kept stay in order,
  // and an own sphere's pairs are all kept: its sum is unchanged.
  void keep_pairs_of_own(NeighbourList<3>& nl) const {
    const auto own = [&](std::uint32_t i) { return i >= below_ && i < below_ + owned_; };
    std::size_t kept = 0;
    for (std::size_t m = 0; m + 1 < nl.offsets.size(); ++m) {
      const std::uint32_t begin = nl.offsets[m], end = nl.offsets[m + 1];
      nl.offsets[m] = static_cast<std::uint32_t>(kept);
      for (std::uint32_t p = begin; p < end; ++p)
        if (own(static_cast<std::uint32_t>(m)) || own(nl.list[p])) nl.list[kept++] = nl.list[p];
    }
    nl.offsets.back() = static_cast<std::uint32_t>(kept);
    nl.list.resize(kept);
    nl.first.resize(kept);
  }

  void carry_springs(NeighbourList<3>& nl) const {
    const auto& id = local_.component<ParticleId>();
    nl.shear.assign(nl.list.size(), Shear{});
    // The spring of the pair (a, b) as listed under a, if this rank has it.
    const auto find = [&](std::uint32_t a, std::uint32_t b, Shear& h) {
      if (was_[a] != none) {
        for (std::uint32_t q = previous_.offsets[was_[a]]; q < previous_.offsets[was_[a] + 1]; ++q)
          if (previous_ids_[previous_.list[q]] == id[b]) {
            h = previous_.shear[q];
            return true;
          }
        return false;
      }
      const auto found = arrived_.find(id[a]);
      if (found == arrived_.end()) return false;
      for (const auto& [partner, spring] : found->second)
        if (partner == id[b]) {
          h = spring;
          return true;
        }
      return false;
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nl.list.size(), 4096), [&](const auto& r) {
      for (std::size_t p = r.begin(); p != r.end(); ++p) nl.shear[p] = carried_spring(nl.first[p], nl.list[p], find);
    });
  }

  const Communicator& ranks_;
  double dt_;
  CellGrid<3> grid_;  // the whole system's list cells
  SlabDomain slab_;   // in layers of grid_ along z
  DemDomainBalance balance_;
  std::int64_t last_balance_ = 0;
  World local_;
  DemKickDrift<3> kick_drift_;
  DemContactForces<3> forces_;
  DemKick<3> kick_;
  bool scattered_ = false, host_current_ = true;
  bool images_ = false, rotating_ = false, sides_ = false;
  std::array<bool, 2> alike_{};  // the whole system's: all masses equal, all radii equal
  std::size_t walls_ = 0;
  std::size_t first_layer_ = 0;  // of the whole system's, held as local layer 0
  // The local World: the copies of the layer below [0, below_), the own
  // spheres [below_, below_ + owned_), the copies of the layer above.
  std::size_t below_ = 0, owned_ = 0;
  std::size_t send_low_ = 0, send_high_ = 0;  // own spheres in the lowest and highest layer
  std::uint64_t first_own_index_ = 0;          // the first own sphere's in the whole system's order
  // A World's columns while it holds this rank's part (lend_part), and its size.
  struct LentColumns {
    std::vector<Vec<3>> x, v, f, omega, torque;
    std::vector<double> mass, radius;
    std::vector<std::uint32_t> id;
    std::vector<typename ImageCount<3>::value_type> image;
    std::vector<std::uint8_t> side;
  } lent_;
  std::size_t lent_from_size_ = 0;
  // During a build: the lists of the last one, the ids of the spheres as
  // they were then, and for each sphere now held where it was then, if
  // this rank owned it (else `none`); the springs that came with spheres
  // from other ranks, by the first sphere's id.
  std::vector<double> pending_;  // the last force pass's sums of the own layers, not yet added over the ranks
  bool pending_valid_ = false;
  std::vector<Vec<3>> spare_vectors_;
  std::vector<double> spare_reals_;
  std::vector<std::uint32_t> spare_ids_;
  std::vector<typename ImageCount<3>::value_type> spare_images_;
  std::vector<std::uint8_t> spare_sides_;
  NeighbourList<3> previous_;
  std::vector<std::uint32_t> previous_ids_, was_;
  std::unordered_map<std::uint32_t, std::vector<std::pair<std::uint32_t, Shear>>> arrived_;
  PhaseTimes<11> times_{{"drift", "agreement", "migration", "copies_at_build", "neighbour_list", "copies",
                         "forces", "energy_terms", "kick", "gather", "energy_at_gather"}};
};

}  // namespace granflow::dem
