// The event-driven gas's state I/O: what a checkpoint keeps of it beside
// the World's components, its restoration, and the checks that refuse a
// saved state no run could have written (systems/edmd/event_driven_gas.hpp).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::edmd {

template <int D>
StateMap EventDrivenGas<D>::save_state() const {
  StateMap out;
  const std::size_t n = world_.size();
  auto& hot = out["hot"];
  auto& plan = out["plan"];
  auto& cell = out["cell"];
  auto& event = out["event_time"];
  for (std::size_t i = 0; i < n; ++i) {
    const MotionRecord<D> record = motion_of(i);
    for (int a = 0; a < D; ++a) hot.push_back(record.x[a]);
    for (int a = 0; a < D; ++a) hot.push_back(record.v[a]);
    hot.push_back(record.t);
    hot.push_back(record.r);
    plan.insert(plan.end(), {plan_[i].collision_time, static_cast<double>(plan_[i].partner),
                             static_cast<double>(plan_[i].partner_count), static_cast<double>(event_kind_[i])});
    cell.push_back(static_cast<double>(grid_.serial(grid_.cell_of(static_cast<std::uint32_t>(i)))));
    event.push_back(calendar_.time_of(static_cast<std::uint32_t>(i)));
  }
  // Each particle's place in its cell's list, 0 at the head.
  auto& place = out["cell_place"];
  place.assign(n, 0.0);
  std::vector<bool> counted(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t c = grid_.cell_of(static_cast<std::uint32_t>(i));
    if (counted[i]) continue;
    double k = 0.0;
    for (std::int32_t m = grid_.head(c); m >= 0; m = grid_.next(static_cast<std::uint32_t>(m)), k += 1.0) {
      place[static_cast<std::size_t>(m)] = k;
      counted[static_cast<std::size_t>(m)] = true;
    }
  }
  const auto& s = statistics_;
  out["scalars"] = {now_, kinetic_energy_, static_cast<double>(next_resort_), static_cast<double>(s.pair_collisions),
                    static_cast<double>(s.wall_collisions), static_cast<double>(s.cell_crossings),
                    static_cast<double>(s.stale_events), s.dissipated_energy, s.wall_dissipated_energy, s.virial};
  out["collapse"] = collapse_.state();
  return out;
}

template <int D>
void EventDrivenGas<D>::restore_state(const StateMap& in) {
  const std::size_t n = world_.size();
  const auto& radius = world_.template component<Radius>();
  const double max_radius = n ? *std::max_element(radius.values.begin(), radius.values.end()) : 0.0;
  grid_.reset(world_.template resource<Box<D>>(), 2.0 * max_radius, n);
  const auto& hot = in.at("hot");
  const auto& plan = in.at("plan");
  const auto& cell = in.at("cell");
  if (hot.size() != n * (2 * D + 2) || plan.size() != 4 * n || cell.size() != n || in.at("event_time").size() != n ||
      in.at("scalars").size() != 10)
    throw std::invalid_argument("checkpoint does not match the number of particles");
  validate_state(in);
  now_ = in.at("scalars").at(0);
  bind();
  plan_.assign(n, Plan{never, 0, 0});
  event_kind_.assign(n, EventKind::none);
  for (std::size_t i = 0; i < n; ++i) {
    const double* h = &hot[i * (2 * D + 2)];
    for (int a = 0; a < D; ++a) hot_[i].x[a] = h[a];
    for (int a = 0; a < D; ++a) hot_[i].v[a] = h[D + a];
    hot_[i].t = h[2 * D];
    hot_[i].r = h[2 * D + 1];
    plan_[i] = Plan{plan[4 * i], static_cast<std::uint32_t>(plan[4 * i + 1]),
                    static_cast<std::uint32_t>(plan[4 * i + 2])};
    event_kind_[i] = static_cast<EventKind>(plan[4 * i + 3]);
  }
  // Lists grow at their heads: inserting from the tail end rebuilds each
  // in its saved order (checkpoints without places get index order).
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  if (const auto place = in.find("cell_place"); place != in.end())
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return place->second[a] > place->second[b]; });
  for (const std::uint32_t i : order) grid_.insert(i, grid_.from_serial(static_cast<std::uint64_t>(cell[i])));
  const auto& s = in.at("scalars");
  calendar_.rebuild(now_, in.at("event_time"));
  kinetic_energy_ = s.at(1);
  next_resort_ = static_cast<std::uint64_t>(s.at(2));
  statistics_.pair_collisions = static_cast<std::uint64_t>(s.at(3));
  statistics_.wall_collisions = static_cast<std::uint64_t>(s.at(4));
  statistics_.cell_crossings = static_cast<std::uint64_t>(s.at(5));
  statistics_.stale_events = static_cast<std::uint64_t>(s.at(6));
  statistics_.dissipated_energy = s.at(7);
  statistics_.wall_dissipated_energy = s.at(8);
  statistics_.virial = s.at(9);
  collapse_.restore(in.at("collapse"));
  // A state saved at a synchronisation (every record at now_) is handed to
  // the World, which moves nothing, as after start(). One saved between
  // events (an interrupted run) stays in the records, where the run goes
  // on from it exactly as it would have without the interruption; the
  // World's motion columns are then not current until synchronize().
  if (std::all_of(hot_.begin(), hot_.begin() + static_cast<std::ptrdiff_t>(n),
                  [&](const MotionRecord<D>& record) { return record.t == now_; })) {
    publish(true);
    kinetic_energy_ = s.at(1);
  }
}

template <int D>
void EventDrivenGas<D>::validate_state(const StateMap& in) const {
  const std::size_t n = world_.size();
  const auto fail = [](const std::string& what) { throw std::invalid_argument("event-driven state: " + what); };
  const auto& box = world_.template resource<Box<D>>();
  const auto& mass = world_.template component<Mass>();
  const auto& id = world_.template component<ParticleId>();
  std::vector<bool> seen(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(mass[i] > 0) || !std::isfinite(mass[i])) fail(fmt::format("particle {} has mass {}", i, mass[i]));
    if (id[i] >= n || seen[id[i]]) fail(fmt::format("particle id {} at {} is out of range or repeated", id[i], i));
    seen[id[i]] = true;
  }
  const auto& s = in.at("scalars");
  const double now = s.at(0);
  if (!std::isfinite(now) || !(s.at(1) >= 0) || !std::isfinite(s.at(1)))
    fail(fmt::format("time {} or kinetic energy {} is impossible", now, s.at(1)));
  for (double v : s)
    if (!std::isfinite(v)) fail("a counter is not finite");
  const auto& hot = in.at("hot");
  for (std::size_t i = 0; i < n; ++i) {
    const double* h = &hot[i * (2 * D + 2)];
    for (int a = 0; a < D; ++a) {
      const double slack = 1e-9 * box.length[a];
      if (!(h[a] >= -slack && h[a] <= box.length[a] + slack))
        fail(fmt::format("particle {} is at {} on axis {}, outside the box [0, {}]", i, h[a], a, box.length[a]));
      if (!std::isfinite(h[D + a])) fail(fmt::format("particle {} has a velocity that is not finite", i));
    }
    if (!std::isfinite(h[2 * D]) || h[2 * D] > now) fail(fmt::format("particle {} has local time {}", i, h[2 * D]));
    if (!(h[2 * D + 1] > 0) || !std::isfinite(h[2 * D + 1])) fail(fmt::format("particle {} has radius {}", i, h[2 * D + 1]));
  }
  const auto& plan = in.at("plan");
  const auto& cell = in.at("cell");
  const auto& event = in.at("event_time");
  const auto cells = static_cast<double>(grid_.cell_total());
  if (const auto place = in.find("cell_place"); place != in.end()) {
    if (place->second.size() != n) fail("cell list places do not match the number of particles");
    for (std::size_t i = 0; i < n; ++i)
      if (!(place->second[i] >= 0 && place->second[i] < static_cast<double>(n)))
        fail(fmt::format("particle {} has cell list place {}", i, place->second[i]));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(plan[4 * i]) || !(plan[4 * i + 1] >= 0 && plan[4 * i + 1] < static_cast<double>(n)) ||
        plan[4 * i + 1] != std::floor(plan[4 * i + 1]) || !(plan[4 * i + 2] >= 0) ||
        !(plan[4 * i + 3] >= 0 && plan[4 * i + 3] < static_cast<double>(crossing_kind(D - 1, true)) + 1) ||
        plan[4 * i + 3] != std::floor(plan[4 * i + 3]))
      fail(fmt::format("particle {} has an impossible planned event", i));
    if (!(cell[i] >= 0 && cell[i] < cells) || cell[i] != std::floor(cell[i]))
      fail(fmt::format("particle {} is in cell {} of {}", i, cell[i], cells));
    if (std::isnan(event[i]) || event[i] < now) fail(fmt::format("particle {} has event time {}", i, event[i]));
  }
}

template StateMap EventDrivenGas<2>::save_state() const;
template StateMap EventDrivenGas<3>::save_state() const;
template void EventDrivenGas<2>::restore_state(const StateMap&);
template void EventDrivenGas<3>::restore_state(const StateMap&);
template void EventDrivenGas<2>::validate_state(const StateMap&) const;
template void EventDrivenGas<3>::validate_state(const StateMap&) const;

}  // namespace granflow::edmd
