#pragma once
// What bounds an advance of the event-driven gas (EventDrivenGas::advance),
// why it stopped, and what it counted on the way.

#include <atomic>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace granflow::edmd {

struct EventStatistics {
  std::uint64_t pair_collisions = 0;
  std::uint64_t wall_collisions = 0;
  std::uint64_t cell_crossings = 0;
  std::uint64_t stale_events = 0;
  double dissipated_energy = 0.0;  // in pair collisions
  double wall_dissipated_energy = 0.0;
  double virial = 0.0;  // sum over collisions of r_ij . delta p_i

  std::uint64_t events() const { return pair_collisions + wall_collisions + cell_crossings + stale_events; }
};

// One velocity-changing event, reported with stable particle ids.
struct EventRecord {
  double time;
  std::uint32_t first;
  std::uint32_t second;  // wall_partner for a wall collision
  static constexpr std::uint32_t wall_partner = std::numeric_limits<std::uint32_t>::max();
};

enum class StopReason { reached_time, collision_limit, energy_limit, collapse, no_events, interrupted };

struct AdvanceLimits {
  std::uint64_t max_pair_collisions = std::numeric_limits<std::uint64_t>::max();
  double min_kinetic_energy = -1.0;
  // When set, advance() returns between two events (state consistent, not synchronised).
  const std::atomic<bool>* interrupt = nullptr;
};

class InelasticCollapse : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace granflow::edmd
