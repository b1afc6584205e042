// The event-driven gas's memory layout: the motion records and the World's
// Position and Velocity holding the particles' motion in turn, their
// handover, the particles' order in memory (cells in Z order) and the
// memory a particle costs (systems/edmd/event_driven_gas.hpp). Built like
// the event loop (CMakeLists.txt), whose handovers these are.

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "engine/core/page_release.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::edmd {

template <int D>
std::size_t EventDrivenGas<D>::bytes_per_particle() const {
  return world_.component_bytes_per_entity() - 2 * sizeof(Vec<D>) +
         sizeof(MotionRecord<D>) + sizeof(Plan) + sizeof(EventKind) + grid_.bytes_per_particle() +
         calendar_.bytes_per_particle();
}

template <int D>
void EventDrivenGas<D>::bind() {
  if (world_.size() >= CandidateList::max_records<D>)
    throw std::invalid_argument(fmt::format("an event-driven gas holds fewer than {} particles, not {}",
                                            CandidateList::max_records<D>, world_.size()));
  mass_ = world_.template component<Mass>().data();
  count_ = world_.template component<CollisionCount>().data();
  last_collision_ =
      parameters_.contact_time > 0.0 ? world_.template component<LastCollisionTime>().data() : nullptr;
  id_ = world_.template component<ParticleId>().data();
  // Periodic images are counted only where a scenario asks for them (MSD).
  image_ = world_.template has_component<ImageCount<D>>() ? world_.template component<ImageCount<D>>().data()
                                                          : nullptr;
  box_ = world_.template resource<Box<D>>();
  walled_ = !std::all_of(box_.periodic.begin(), box_.periodic.end(), [](bool p) { return p; });
  // One record more, the sentinel that pads the candidate list: its NaN
  // position fails every contact test.
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  hot_.resize(world_.size() + 1);
  hot_[world_.size()] = {Vec<D>::Constant(nan), Vec<D>::Zero(), 0.0, 0.0};
  take_back();
}

template <int D>
void EventDrivenGas<D>::publish(bool release_records) {
  auto& position = world_.template component<Position<D>>();
  auto& velocity = world_.template component<Velocity<D>>();
  const std::size_t n = world_.size();
  double energy = 0.0;
  for (std::size_t begin = 0; begin < n; begin += handover_block) {
    const std::size_t end = std::min(n, begin + handover_block);
    for (std::size_t i = begin; i < end; ++i) {
      advance_particle(static_cast<std::uint32_t>(i));
      position[i] = hot_[i].x;
      velocity[i] = hot_[i].v;
      energy += 0.5 * mass_[i] * hot_[i].v.squaredNorm();
    }
    if (release_records) release_pages(&hot_[begin], (end - begin) * sizeof(MotionRecord<D>));
  }
  kinetic_energy_ = energy;
  records_hold_motion_ = false;
  release_world_motion_ = release_records;
}

template <int D>
void EventDrivenGas<D>::take_back() {
  auto& position = world_.template component<Position<D>>();
  auto& velocity = world_.template component<Velocity<D>>();
  const auto& radius = world_.template component<Radius>();
  const std::size_t n = world_.size();
  for (std::size_t begin = 0; begin < n; begin += handover_block) {
    const std::size_t end = std::min(n, begin + handover_block);
    for (std::size_t i = begin; i < end; ++i) hot_[i] = {position[i], velocity[i], now_, radius[i]};
    if (!release_world_motion_) continue;
    release_pages(&position[begin], (end - begin) * sizeof(Vec<D>));
    release_pages(&velocity[begin], (end - begin) * sizeof(Vec<D>));
  }
  records_hold_motion_ = true;
  events_at_take_back_ = statistics_.events();
}

template <int D>
MotionRecord<D> EventDrivenGas<D>::motion_of(std::size_t i) const {
  if (records_hold_motion_) return hot_[i];
  return {world_.template component<Position<D>>()[i], world_.template component<Velocity<D>>()[i], now_,
          world_.template component<Radius>()[i]};
}

template <int D>
std::uint64_t EventDrivenGas<D>::morton_key(const std::array<std::int32_t, D>& c) {
  std::uint64_t code = 0;
  for (int bit = 0; bit < 21; ++bit)
    for (int a = 0; a < D; ++a)
      code |= static_cast<std::uint64_t>((c[a] >> bit) & 1) << (bit * D + a);
  return code;
}

template <int D>
void EventDrivenGas<D>::sort_by_cell() {
  const auto& position = world_.template component<Position<D>>();
  std::vector<std::uint64_t> morton(world_.size());
  for (std::size_t i = 0; i < world_.size(); ++i)
    morton[i] = morton_key(grid_.coordinates(grid_.locate(position[i])));
  std::vector<std::uint32_t> order(world_.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return morton[a] < morton[b]; });
  world_.permute(order);
}

#define GRANFLOW_LAYOUT_MEMBERS(D)                                                                  \
  template std::size_t EventDrivenGas<D>::bytes_per_particle() const;                               \
  template void EventDrivenGas<D>::bind();                                                          \
  template void EventDrivenGas<D>::publish(bool);                                                   \
  template void EventDrivenGas<D>::take_back();                                                     \
  template MotionRecord<D> EventDrivenGas<D>::motion_of(std::size_t) const;                         \
  template std::uint64_t EventDrivenGas<D>::morton_key(const std::array<std::int32_t, D>&);         \
  template void EventDrivenGas<D>::sort_by_cell();
GRANFLOW_LAYOUT_MEMBERS(2)
GRANFLOW_LAYOUT_MEMBERS(3)
#undef GRANFLOW_LAYOUT_MEMBERS

}  // namespace granflow::edmd
