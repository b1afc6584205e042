#pragma once
// Turns a list of systems into a oneTBB flow graph. Edges come only from the
// declared accesses: a later system waits for an earlier one when either
// writes something the other touches; systems with disjoint needs may run
// concurrently. When the edges chain every system to the next (the usual
// time step: each system needs the previous one's result), the graph is run
// as a plain loop instead, which costs nothing per step.

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/profiler.hpp"
#include "engine/core/system.hpp"

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
  // Runs the systems whose `enabled` entry is true (in graph order); the
  // others are skipped and not counted.
  void run(World& world, const std::vector<bool>& enabled);
  // The same one system at a time, in the order they were added: for systems
  // that make collective calls (observers over MPI ranks), which every rank
  // must make in one order.
  void run_in_order(World& world, const std::vector<bool>& enabled);

  // (earlier, later) index pairs of the derived edges, after transitive reduction.
  std::vector<std::pair<std::size_t, std::size_t>> edges() const;
  // True when the systems form one dependent chain and run as a plain loop.
  bool sequential() const;
  const std::vector<std::unique_ptr<System>>& systems() const { return systems_; }
  std::size_t size() const { return systems_.size(); }

 private:
  void build() const;
  void run_one(std::size_t k, World& world);

  struct Graph;
  Profiler& profiler_;
  std::vector<std::unique_ptr<System>> systems_;
  std::vector<std::size_t> profile_slots_;
  mutable std::unique_ptr<Graph> graph_;
  World* current_world_ = nullptr;
  const std::vector<bool>* enabled_ = nullptr;
};

}  // namespace granflow
