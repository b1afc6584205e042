#pragma once
// Event-driven dynamics of smooth inelastic hard spheres (D = 3) and disks
// (D = 2), one code path for both.
//
// The algorithm follows the fastest published codes rather than a loop that
// moves every particle and tests all pairs at every event:
//  * delayed states: a particle's position holds at its own local time, and
//    only the particles in an event are advanced (Marin, Risso & Cordero 1993);
//  * what a prediction reads of a neighbour (position, velocity, local time,
//    radius) is packed in one 64-byte record, one cache line per neighbour;
//    the records and the World's Position and Velocity take turns to hold
//    the particles' motion (the records while events run, the World from
//    synchronize() on), and where synchronisations are rare they are never
//    both resident in memory;
//  * a cell list with cell-crossing events, so a prediction looks only at the
//    3^D surrounding cells, through periodic images where the box is periodic;
//  * one scheduled event per particle, its earliest; a collision stored
//    against a partner is checked against the partner's CollisionCount when it
//    comes up and re-predicted lazily if stale (Smallenburg 2022);
//  * an O(1) calendar that retunes itself as a granular gas cools;
//  * particles sorted by cell at start so neighbours are close in memory.
// Round-off overlaps are resolved as immediate collisions of approaching pairs
// (see contact_time), never as pass-through or endless zero-time loops, and a
// runaway collision rate (inelastic collapse) stops the run with a diagnosis.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "components/box.hpp"
#include "components/collision_count.hpp"
#include "components/image_count.hpp"
#include "components/last_collision_time.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/config.hpp"
#include "engine/core/page_release.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/world.hpp"
#include "systems/edmd/advance_limits.hpp"
#include "systems/edmd/candidate_list.hpp"
#include "systems/edmd/cell_grid.hpp"
#include "systems/edmd/collapse_monitor.hpp"
#include "systems/edmd/collision_parameters.hpp"
#include "systems/edmd/viscoelastic_restitution.hpp"
#include "systems/edmd/collision_rule.hpp"
#include "systems/edmd/contact_search.hpp"
#include "systems/edmd/event_calendar.hpp"
#include "systems/edmd/motion_record.hpp"
#include "systems/edmd/occupied_cells.hpp"

namespace granflow::edmd {

template <int D>
class EventDrivenGas : public Stateful {
 public:
  static constexpr const char* key = "event_driven_gas";

  // The world must hold Box<D> and the Position, Velocity, Mass and Radius
  // components; the engine adds what it needs besides.
  EventDrivenGas(World& world, const CollisionParameters& parameters, bool sort_in_space = true)
      : world_(world), parameters_(parameters), sort_in_space_(sort_in_space) {
    world.add_component<CollisionCount>();
    // Collision times are only needed by the TC model.
    if (parameters.contact_time > 0.0 && !world.has_component<LastCollisionTime>()) {
      auto& last = world.add_component<LastCollisionTime>();
      std::fill(last.values.begin(), last.values.end(), -std::numeric_limits<double>::infinity());
    }
    if (!world.has_component<ParticleId>()) {
      auto& id = world.add_component<ParticleId>();
      std::iota(id.values.begin(), id.values.end(), 0u);
    }
  }

  // Prepares cells and events with every particle at time `now`; the World
  // holds the particles' motion afterwards, as it did before.
  void start(double now) {
    // What the set-up freed (a preparation's gas, placement grids) goes
    // back to the system before this gas's arrays are laid out.
    return_freed_memory();
    const auto& box = world_.template resource<Box<D>>();
    const std::size_t count = world_.size();
    auto& radius = world_.template component<Radius>();
    const double max_radius = count ? *std::max_element(radius.values.begin(), radius.values.end()) : 0.0;
    for (int a = 0; a < D; ++a)
      if (box.length[a] <= 4.0 * max_radius)
        throw std::invalid_argument(fmt::format(
            "box length {} along axis {} must exceed two particle diameters ({})", box.length[a], a, 4 * max_radius));
    grid_.reset(box, 2.0 * max_radius, count);
    rebuild(now);
    publish(true);
    collapse_.reset(count, now, kinetic_energy_);
    next_resort_ = statistics_.pair_collisions + resort_interval();
  }

  // Processes events up to time `until` (inclusive) or until a limit is hit.
  // Particles are left at their own local times, and the World's Position
  // and Velocity are garbage until synchronize() is called.
  // Kept out of line, so that the event loop and everything it inlines is
  // the code of event_driven_gas.cpp, built for the kernels' instruction set,
  // wherever a gas is advanced.
  [[gnu::noinline]] StopReason advance(double until, const AdvanceLimits& limits = {}) {
    if (!records_hold_motion_) take_back();
    while (true) {
      if (statistics_.pair_collisions >= limits.max_pair_collisions) return StopReason::collision_limit;
      if (kinetic_energy_ <= limits.min_kinetic_energy) return StopReason::energy_limit;
      if (limits.interrupt && limits.interrupt->load(std::memory_order_relaxed)) return StopReason::interrupted;
      const std::uint32_t i = calendar_.earliest([this](std::uint32_t k) { fetch_ahead(k); });
      if (i == EventCalendar::none) {
        now_ = std::max(now_, until);
        return StopReason::no_events;
      }
      const double t = calendar_.time_of(i);
      if (t > until) {
        now_ = until;
        return StopReason::reached_time;
      }
      now_ = t;
      process(i);
      if (statistics_.pair_collisions >= next_resort_) resort();
      if (collapse_.observe(statistics_.pair_collisions, now_, kinetic_energy_, parameters_.collapse_rate_factor)) {
        collapse_message_ = collapse_.diagnosis(parameters_.contact_time);
        return StopReason::collapse;
      }
    }
  }

  // Moves every particle to time t >= time of the last event and hands
  // positions and velocities to the World.
  void synchronize(double t) {
    const double from = now_;
    now_ = std::max(now_, t);
    if (records_hold_motion_) {
      publish(statistics_.events() - events_at_take_back_ >= release_after_events_ * world_.size());
      return;
    }
    // Synchronised before, at `from`: the same motion the records would get.
    if (now_ == from) return;
    auto& position = world_.template component<Position<D>>();
    const auto& velocity = world_.template component<Velocity<D>>();
    for (std::size_t i = 0; i < world_.size(); ++i) position[i] += velocity[i] * (now_ - from);
  }

  // Current velocity of the particle at storage index i, for an event
  // observer (valid between events, inside advance()).
  const Vec<D>& velocity(std::size_t i) const { return hot_[i].v; }

  double time() const { return now_; }
  double kinetic_energy() const { return kinetic_energy_; }
  const EventStatistics& statistics() const { return statistics_; }
  const std::string& collapse_message() const { return collapse_message_; }
  const CellGrid<D>& grid() const { return grid_; }
  const CollisionParameters& parameters() const { return parameters_; }

  void set_event_observer(std::function<void(const EventRecord&)> observer) { observer_ = std::move(observer); }

  // Everything the engine needs to continue exactly where it was, beside the
  // World's components (kept in the same storage order), as flat arrays.
  // The cell lists keep their order too: it is the order in which a
  // prediction meets its candidates, and a resumed run follows the
  // uninterrupted one bit for bit only if its predictions do.
  StateMap save_state() const override;

  // Continues from save_state() output; the World must hold the components
  // as they were when it was saved.
  void restore_state(const StateMap& in) override;

  // Re-sort every `pair_collisions` collisions whatever the size (0: the
  // automatic choice, which re-sorts only gases larger than the cache);
  // takes effect at the next start() or re-sort.
  void set_resort_interval(std::uint64_t pair_collisions) { resort_every_ = pair_collisions; }
  std::uint64_t resorts() const { return resorts_; }

  // A synchronisation hands the pages of one copy of the motion back to the
  // system only if at least this many events per particle ran since the
  // previous one (0: every time, for the least memory); see publish().
  static constexpr std::uint64_t default_release_after_events = 16;
  void set_release_after_events(std::uint64_t per_particle) { release_after_events_ = per_particle; }

  // Refuses a saved state that could not have come from a run (damaged or
  // crafted), naming what is wrong, before any of it is used as an index.
  void validate_state(const StateMap& in) const;

  // Memory the engine and the components it uses hold per particle while
  // events run (the World's positions and velocities are then released).
  std::size_t bytes_per_particle() const;

 private:
  // Event kinds: a collision with `partner_`, a wall on axis k (wall + k), or
  // leaving the cell through face k (crossing + k, k = 2 * axis + (v > 0)).
  enum class EventKind : std::uint8_t { none = 0, collision = 1, wall = 2, crossing = 2 + D };

  static EventKind wall_kind(int axis) { return static_cast<EventKind>(static_cast<int>(EventKind::wall) + axis); }
  static EventKind crossing_kind(int axis, bool upward) {
    return static_cast<EventKind>(static_cast<int>(EventKind::crossing) + 2 * axis + (upward ? 1 : 0));
  }

  // Sorts particles by cell, then predicts every event afresh; all particles
  // must be at time `now` in the World, and the records hold them afterwards.
  void rebuild(double now) {
    const std::size_t count = world_.size();
    if (sort_in_space_) {
      sort_by_cell();
      return_freed_memory();  // the sort's keys and the columns' old copies
    }
    now_ = now;
    bind();
    grid_.clear();
    for (std::uint32_t i = 0; i < count; ++i) grid_.insert(i, grid_.locate(hot_[i].x));
    plan_.assign(count, Plan{never, 0, 0});
    event_kind_.assign(count, EventKind::none);
    calendar_.rebuild(now, count, [this](std::uint32_t i) { return predict(i); });
  }

  // Particles drift away from their neighbours in memory as the gas moves;
  // once the data no longer fits in cache, re-sorting every few collisions
  // per particle costs far less than the cache misses it saves.
  std::uint64_t resort_interval() const {
    if (resort_every_ > 0) return resort_every_;
    constexpr std::size_t cache_resident = 32768;
    if (!sort_in_space_ || world_.size() < cache_resident) return std::numeric_limits<std::uint64_t>::max() / 2;
    return 5 * world_.size();  // 10 collisions per particle
  }

  void resort() {
    ++resorts_;
    // Every event is predicted afresh, which costs more than the page faults
    // of a full handover: the records' memory and the old events' are
    // released before the sort needs room for its keys and copies.
    publish(true);
    release_pages(plan_);
    release_pages(event_kind_);
    calendar_.release_events();
    grid_.release_lists();
    rebuild(now_);  // takes the motion back: events run on
    next_resort_ = statistics_.pair_collisions + resort_interval();
  }

  void bind();

  // The records and the World's Position and Velocity hold the motion in
  // turn, copied a block at a time with each block's source released as it
  // goes, so that the copy never has both resident: at 10^6 particles that
  // is 48 MB of the peak. A released page costs a page fault when it is
  // written again, up to 8 us on a virtual machine: about one event's time
  // per particle for a handover there and back. Only synchronisations at
  // least 16 events per particle apart (10 % of the events' time or less)
  // hand the pages back; closer ones, as a run that observes often makes
  // them, keep both copies resident.
  static constexpr std::size_t handover_block = std::size_t{1} << 14;

  // From the records to the World, every particle moved to now_ first;
  // `release_records`: whether the records' pages, and at the next
  // take_back() the World's, go back to the system.
  void publish(bool release_records);

  // From the World (all particles at now_) to the records.
  void take_back();

  // Particle i's record, from wherever the motion is held.
  MotionRecord<D> motion_of(std::size_t i) const;

  // Z-order (Morton) of the cells: a cell's neighbours in every direction
  // lie in a few short runs of memory, not in 3^(D-1) rows far apart.
  static std::uint64_t morton_key(const std::array<std::int32_t, D>& c);

  void sort_by_cell();

  // Asks the memory for what particle k's event will read first, a few
  // events before it comes: events come in time order, so their particles'
  // data lie at random addresses, and beyond the caches (N of 10^4 and
  // more) each of these lines would otherwise be waited for in turn.
  void fetch_ahead(std::uint32_t k) const {
    __builtin_prefetch(&hot_[k]);
    __builtin_prefetch(&plan_[k]);
    __builtin_prefetch(&event_kind_[k]);
    __builtin_prefetch(grid_.membership(k));
  }

  void advance_particle(std::uint32_t i) {
    hot_[i].x += hot_[i].v * (now_ - hot_[i].t);
    hot_[i].t = now_;
  }

  struct BoundaryEvent {
    double time;
    EventKind kind;
  };
  // Earliest wall contact or cell crossing of particle i (at time now_ in
  // cell `cell`): never and none if the particle is at rest.
  [[gnu::always_inline]] BoundaryEvent boundary_event(std::uint32_t i, const std::array<std::int32_t, D>& cell) const {
    EventKind kind = EventKind::none;
    const Vec<D>& xi = hot_[i].x;
    const Vec<D>& vi = hot_[i].v;
    const double ri = hot_[i].r;
    double earliest = never;
    for (int a = 0; a < D; ++a) {
      const double v = vi[a];
      // A zero velocity (either sign) then divides a distance of its own
      // sign, or zero: +infinity or NaN, neither ever the earliest.
      const bool upward = !std::signbit(v);
      double dt = ((cell[a] + (upward ? 1 : 0)) * grid_.width(a) - xi[a]) / v;
      EventKind k = crossing_kind(a, upward);
      if (walled_ && !box_.periodic[a] && (upward ? cell[a] == grid_.count(a) - 1 : cell[a] == 0)) {
        dt = ((upward ? box_.length[a] - ri : ri) - xi[a]) / v;
        k = wall_kind(a);
      }
      // Masks, not a branch: which axis comes first is a coin toss, and
      // GCC turns a plain `if` here into a mispredicted jump (6 % of the
      // time per collision at packing fraction 0.065).
      const auto earlier = static_cast<std::uint8_t>(-static_cast<int>(dt < earliest));
      kind = static_cast<EventKind>((static_cast<std::uint8_t>(k) & earlier) |
                                    (static_cast<std::uint8_t>(kind) & static_cast<std::uint8_t>(~earlier)));
      earliest = std::min(earliest, dt);
    }
    // A negative time (a particle a rounding error outside its cell) means now.
    return {now_ + std::max(earliest, 0.0), kind};
  }

  // Stores particle i's earliest collision and returns the time of its earliest event.
  double conclude(std::uint32_t i, BoundaryEvent boundary, double best_collision, std::uint32_t partner) {
    double best = boundary.time;
    EventKind kind = boundary.kind;
    if (best_collision < never) {
      plan_[i].collision_time = best_collision;
      plan_[i].partner = partner;
      plan_[i].partner_count = count_[partner];
    } else {
      plan_[i].collision_time = never;
    }
    if (best_collision <= best) {
      best = best_collision;
      kind = best < never ? EventKind::collision : EventKind::none;
    }
    event_kind_[i] = kind;
    return best;
  }

  // Lists as candidates the particles of the cells at `offsets` from `here`
  // whose bits are set in `occupied` (their heads in `heads`), in the order
  // of the offsets, with the periodic image each cell is seen through where
  // the walk reaches halo cells (Shifted).
  template <bool Shifted>
  [[gnu::always_inline]] void gather(CandidateList::Writer<D>& writer, std::uint32_t here, const std::int32_t* offsets,
                                     std::uint64_t occupied, const std::int32_t* heads) {
    const auto next = [this](std::uint32_t k) { return grid_.next(k); };
    for (; occupied != 0; occupied &= occupied - 1) {
      const auto k = static_cast<std::size_t>(__builtin_ctzll(occupied));
      if constexpr (Shifted)
        writer.append_shifted_list(heads[k], next,
                                   grid_.shift_offset(static_cast<std::uint32_t>(static_cast<std::int32_t>(here) + offsets[k])));
      else
        writer.append_list(heads[k], next);
    }
  }

  CandidateList::Writer<D> start_candidates() {
    return candidates_.refill(hot_.data(), static_cast<std::int32_t>(world_.size()), CellGrid<D>::unshifted_offset);
  }
  // Most predictions see no periodic image; theirs skip the shifts.
  EarliestContact earliest_among(std::size_t begin, std::size_t end, std::uint32_t i, bool images) {
    return earliest_contact<D>(candidates_, begin, end, hot_.data(), images ? grid_.shift_table() : nullptr,
                               CellGrid<D>::unshifted_offset, hot_[i], now_);
  }

  // Re-predicts the two particles of a collision in one pass: they are
  // neighbours, so most of their 3^D neighbour cells are shared, and each
  // shared cell is copied once for both. Same results as predict() for each
  // (up to the order in which exactly equal times of different partners are
  // compared). Falls back to two predictions for a pair on opposite sides of
  // a periodic face.
  void repredict_pair(std::uint32_t i, std::uint32_t j) {
    const std::uint32_t here_i = grid_.cell_of(i);
    const auto ci = grid_.coordinates(here_i);
    const auto cj = grid_.coordinates(grid_.cell_of(j));
    const auto& walk = grid_.pair_walk(ci, cj);
    if (walk.total == 0) {
      repredict(i);
      repredict(j);
      return;
    }
    // i tests the cells only it sees and the shared ones, j the shared ones
    // and its own. Neither need be left out: the pair has just collided, so
    // it recedes, and a particle never approaches itself.
    std::int32_t heads[CellGrid<D>::padded(2 * CellGrid<D>::neighbour_count)];
    const std::int32_t* offsets = walk.offsets.data();
    const std::uint64_t occupied = occupied_cells(grid_.heads(), here_i, offsets, walk.total, heads);
    const auto below = [](int k) { return (std::uint64_t{1} << k) - 1; };
    auto writer = start_candidates();
    std::size_t shared_begin = 0, shared_end = 0;
    const auto fill = [&](auto shifted) {
      constexpr bool with_shifts = decltype(shifted)::value;
      gather<with_shifts>(writer, here_i, offsets, occupied & below(walk.first_only), heads);
      shared_begin = writer.size();
      gather<with_shifts>(writer, here_i, offsets, occupied & below(walk.shared_end) & ~below(walk.first_only), heads);
      shared_end = writer.size();
      gather<with_shifts>(writer, here_i, offsets, occupied & ~below(walk.shared_end), heads);
    };
    const bool images = grid_.sees_images(here_i) || grid_.sees_images(grid_.cell_of(j));
    if (images) fill(std::true_type{});
    else fill(std::false_type{});
    writer.close();
    const auto for_i = earliest_among(0, shared_end, i, images);
    const auto for_j = earliest_among(shared_begin, candidates_.size(), j, images);
    calendar_.schedule(i, conclude(i, boundary_event(i, ci), for_i.time, candidates_.template index<D>(for_i.position)));
    calendar_.schedule(j, conclude(j, boundary_event(j, cj), for_j.time, candidates_.template index<D>(for_j.position)));
  }

  // Finds particle i's earliest event; i must be at time now_.
  // Returns its time; records its kind and partner.
  double predict(std::uint32_t i) { return predict(i, grid_.coordinates(grid_.cell_of(i)), -1); }
  // The same for particle i in the cell at `cell` (its coordinates). After
  // a cell crossing through `entered_face` only the cells that have just
  // become adjacent are scanned (9 of 27 in 3D): the particle's trajectory is
  // unchanged, so its stored earliest collision with the old neighbours
  // still holds, provided that partner has not changed course.
  double predict(std::uint32_t i, const typename CellGrid<D>::Coordinates& cell, int entered_face) {
    const std::uint32_t here = grid_.cell_of(i);
    const bool keeps_collision =
        entered_face >= 0 && (plan_[i].collision_time == never || count_[plan_[i].partner] == plan_[i].partner_count);
    // A stale stored collision makes it scan everything.
    const std::int32_t* offsets = keeps_collision ? grid_.entered_cells(entered_face) : grid_.neighbour_offsets();
    std::int32_t heads[CellGrid<D>::padded(CellGrid<D>::neighbour_count)];
    const std::uint64_t occupied = occupied_cells(
        grid_.heads(), here, offsets, keeps_collision ? CellGrid<D>::entered_count : CellGrid<D>::neighbour_count,
        heads);
    auto writer = start_candidates();
    const bool images = grid_.sees_images(here);
    if (images) gather<true>(writer, here, offsets, occupied, heads);
    else gather<false>(writer, here, offsets, occupied, heads);
    writer.close();
    // i itself need not be left out: a particle never approaches itself.
    const auto earliest = earliest_among(0, candidates_.size(), i, images);
    // Read only now, so that nothing but i stays in registers across the
    // candidate walk.
    double best_collision = keeps_collision ? plan_[i].collision_time : never;
    std::uint32_t partner = plan_[i].partner;
    if (earliest.time < best_collision) {
      best_collision = earliest.time;
      partner = candidates_.template index<D>(earliest.position);
    }
    return conclude(i, boundary_event(i, cell), best_collision, partner);
  }

  void repredict(std::uint32_t i) { calendar_.schedule(i, predict(i)); }

  void process(std::uint32_t i) {
    const EventKind kind = event_kind_[i];
    if (kind == EventKind::collision) {
      const std::uint32_t j = plan_[i].partner;
      advance_particle(i);
      if (count_[j] != plan_[i].partner_count) {
        ++statistics_.stale_events;
        repredict(i);
        return;
      }
      advance_particle(j);
      collide(i, j);
      repredict_pair(i, j);
    } else if (kind < EventKind::crossing) {
      advance_particle(i);
      const int axis = static_cast<int>(kind) - static_cast<int>(EventKind::wall);
      const bool elastic = last_collision_ && now_ - last_collision_[i] < parameters_.contact_time;
      const double restitution = elastic ? 1.0 : parameters_.wall_restitution;
      const double lost = reflect_from_wall<D>(hot_[i].v, mass_[i], axis, restitution);
      statistics_.wall_dissipated_energy += lost;
      kinetic_energy_ -= lost;
      ++statistics_.wall_collisions;
      ++count_[i];
      if (last_collision_) last_collision_[i] = now_;
      if (observer_) observer_({now_, id_[i], EventRecord::wall_partner});
      repredict(i);
    } else {
      advance_particle(i);
      const int face = static_cast<int>(kind) - static_cast<int>(EventKind::crossing);
      calendar_.schedule(i, predict(i, cross_cell(i, face), face));
    }
  }

  void collide(std::uint32_t i, std::uint32_t j) {
    // Both are wrapped into the box and in contact, less than half a box
    // length apart through the nearest image, so one comparison per axis
    // finds that image.
    Vec<D> dx = hot_[j].x - hot_[i].x;
    for (int a = 0; a < D; ++a)
      if (box_.periodic[a]) {
        if (dx[a] > 0.5 * box_.length[a]) dx[a] -= box_.length[a];
        else if (dx[a] < -0.5 * box_.length[a]) dx[a] += box_.length[a];
      }
    const bool elastic =
        last_collision_ && (now_ - last_collision_[i] < parameters_.contact_time ||
                            now_ - last_collision_[j] < parameters_.contact_time);
    double restitution = parameters_.restitution;
    if (viscoelastic_.on()) {
      // Normal impact speed: the approach along the line of centres.
      const double approach = -(hot_[j].v - hot_[i].v).dot(dx);
      restitution = viscoelastic_(approach > 0.0 ? approach / std::sqrt(dx.squaredNorm()) : 0.0);
    }
    const auto result = collide_pair<D>(hot_[i].v, hot_[j].v, mass_[i], mass_[j], dx, elastic ? 1.0 : restitution);
    statistics_.dissipated_energy += result.dissipated_energy;
    statistics_.virial += result.virial;
    kinetic_energy_ -= result.dissipated_energy;
    ++statistics_.pair_collisions;
    ++count_[i];
    ++count_[j];
    if (last_collision_) last_collision_[i] = last_collision_[j] = now_;
    if (observer_) observer_({now_, id_[i], id_[j]});
  }

  // Moves particle i into the next cell through `face`; returns that cell's coordinates.
  typename CellGrid<D>::Coordinates cross_cell(std::uint32_t i, int face) {
    const int axis = face / 2;
    const bool upward = face % 2 == 1;
    const std::uint32_t from = grid_.cell_of(i);
    auto c = grid_.coordinates(from);
    c[axis] += upward ? 1 : -1;
    std::int32_t step = upward ? grid_.stride(axis) : -grid_.stride(axis);
    if (c[axis] == grid_.count(axis)) {
      c[axis] = 0;
      step -= grid_.count(axis) * grid_.stride(axis);
      hot_[i].x[axis] -= box_.length[axis];
      if (image_) ++image_[i][axis];
    } else if (c[axis] < 0) {
      c[axis] = grid_.count(axis) - 1;
      step += grid_.count(axis) * grid_.stride(axis);
      hot_[i].x[axis] += box_.length[axis];
      if (image_) --image_[i][axis];
    }
    ++statistics_.cell_crossings;
    grid_.erase(i);
    grid_.insert(i, static_cast<std::uint32_t>(static_cast<std::int32_t>(from) + step));
    return c;
  }

  World& world_;
  CollisionParameters parameters_;
  ViscoelasticRestitution viscoelastic_{parameters_.viscoelastic_speed};
  bool sort_in_space_;
  Box<D> box_;
  // Whether any axis has walls: a fully periodic box skips their test.
  bool walled_ = false;
  CellGrid<D> grid_;
  EventCalendar calendar_;
  CollapseMonitor collapse_;

  std::vector<MotionRecord<D>> hot_;
  // Whether the records hold the particles' motion (else the World does).
  bool records_hold_motion_ = false;
  // Whether the next take_back() releases the World's Position and Velocity.
  bool release_world_motion_ = true;
  std::uint64_t events_at_take_back_ = 0;
  std::uint64_t release_after_events_ = default_release_after_events;
  double* mass_ = nullptr;
  std::uint32_t* count_ = nullptr;
  double* last_collision_ = nullptr;
  std::uint32_t* id_ = nullptr;
  Eigen::Matrix<std::int32_t, D, 1>* image_ = nullptr;

  // A particle's earliest collision (possibly later than its event), that
  // partner and the partner's collision count at prediction, in 16 bytes;
  // the kind of its scheduled event is kept apart to stay in that size.
  struct Plan {
    double collision_time;
    std::uint32_t partner;
    std::uint32_t partner_count;
  };
  std::vector<Plan> plan_;
  std::vector<EventKind> event_kind_;
  // Scratch of a prediction, kept to avoid allocating per event.
  CandidateList candidates_;

  double now_ = 0.0;
  double kinetic_energy_ = 0.0;
  std::uint64_t next_resort_ = 0;
  std::uint64_t resort_every_ = 0;
  std::uint64_t resorts_ = 0;
  EventStatistics statistics_;
  std::string collapse_message_;
  std::function<void(const EventRecord&)> observer_;
};

// Instantiated once, in event_driven_gas.cpp.
extern template class EventDrivenGas<2>;
extern template class EventDrivenGas<3>;

}  // namespace granflow::edmd
