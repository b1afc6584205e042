#pragma once
// Turns a scenario's systems into a oneTBB flow graph. Edges come only from
// the declared accesses: a later system waits for an earlier one when either
// writes something the other touches; systems with disjoint needs may run
// concurrently.

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/profiler.hpp"
#include "engine/system.hpp"

namespace granflow {

class World;

class Schedule {
 public:
  explicit Schedule(Profiler& profiler);
  ~Schedule();
  Schedule(const Schedule&) = delete;
  Schedule& operator=(const Schedule&) = delete;

  // Systems run in an order consistent with the order they were added.
  System& add(std::unique_ptr<System> system);

  template <class S, class... Args>
  S& emplace(Args&&... args) {
    return static_cast<S&>(add(std::make_unique<S>(std::forward<Args>(args)...)));
  }

  // Runs every system once, in graph order.
  void run(World& world);

  // (earlier, later) index pairs of the derived edges, after transitive reduction.
  std::vector<std::pair<std::size_t, std::size_t>> edges() const;
  const std::vector<std::unique_ptr<System>>& systems() const { return systems_; }

 private:
  void build();

  struct Graph;
  Profiler& profiler_;
  std::vector<std::unique_ptr<System>> systems_;
  std::vector<std::size_t> profile_slots_;
  std::unique_ptr<Graph> graph_;
  World* current_world_ = nullptr;
};

// True when two systems may not run at the same time.
bool accesses_conflict(const Access& a, const Access& b);

}  // namespace granflow
