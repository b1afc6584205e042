#include "engine/core/schedule.hpp"

#include <tbb/flow_graph.h>

namespace granflow {

struct Schedule::Graph {
  tbb::flow::graph graph;
  tbb::flow::broadcast_node<tbb::flow::continue_msg> start{graph};
  std::vector<std::unique_ptr<tbb::flow::continue_node<tbb::flow::continue_msg>>> nodes;
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  bool chain = true;
};

Schedule::Schedule(Profiler& profiler) : profiler_(profiler) {}
Schedule::~Schedule() = default;

System& Schedule::add(std::unique_ptr<System> system) {
  profile_slots_.push_back(profiler_.register_system(system->name()));
  systems_.push_back(std::move(system));
  graph_.reset();
  return *systems_.back();
}

void Schedule::build() const {
  graph_ = std::make_unique<Graph>();
  const std::size_t count = systems_.size();
  std::vector<Access> accesses;
  for (const auto& system : systems_) accesses.push_back(system->access());

  // reach[k][j]: system j must finish before k starts (directly or transitively).
  std::vector<std::vector<bool>> reach(count, std::vector<bool>(count, false));
  for (std::size_t later = 0; later < count; ++later) {
    for (std::size_t earlier = later; earlier-- > 0;) {
      if (!accesses_conflict(accesses[earlier], accesses[later]) || reach[later][earlier]) continue;
      graph_->edges.emplace_back(earlier, later);
      reach[later][earlier] = true;
      for (std::size_t k = 0; k < count; ++k)
        if (reach[earlier][k]) reach[later][k] = true;
    }
  }
  for (std::size_t k = 1; k < count; ++k)
    if (!reach[k][k - 1]) graph_->chain = false;
  if (graph_->chain) return;

  auto* self = const_cast<Schedule*>(this);
  for (std::size_t k = 0; k < count; ++k) {
    graph_->nodes.push_back(std::make_unique<tbb::flow::continue_node<tbb::flow::continue_msg>>(
        graph_->graph, [self, k](const tbb::flow::continue_msg&) {
          if (!self->enabled_ || (*self->enabled_)[k]) self->run_one(k, *self->current_world_);
        }));
  }
  std::vector<bool> has_predecessor(count, false);
  for (auto [earlier, later] : graph_->edges) {
    tbb::flow::make_edge(*graph_->nodes[earlier], *graph_->nodes[later]);
    has_predecessor[later] = true;
  }
  for (std::size_t k = 0; k < count; ++k)
    if (!has_predecessor[k]) tbb::flow::make_edge(graph_->start, *graph_->nodes[k]);
}

void Schedule::run_one(std::size_t k, World& world) {
  ScopedTimer timer(profiler_, profile_slots_[k]);
  systems_[k]->run(world);
}

void Schedule::run(World& world) {
  if (!graph_) build();
  if (graph_->chain) {
    for (std::size_t k = 0; k < systems_.size(); ++k) run_one(k, world);
    return;
  }
  current_world_ = &world;
  enabled_ = nullptr;
  graph_->start.try_put(tbb::flow::continue_msg{});
  graph_->graph.wait_for_all();
  current_world_ = nullptr;
}

void Schedule::run(World& world, const std::vector<bool>& enabled) {
  if (!graph_) build();
  if (graph_->chain) {
    for (std::size_t k = 0; k < systems_.size(); ++k)
      if (enabled[k]) run_one(k, world);
    return;
  }
  current_world_ = &world;
  enabled_ = &enabled;
  graph_->start.try_put(tbb::flow::continue_msg{});
  graph_->graph.wait_for_all();
  current_world_ = nullptr;
  enabled_ = nullptr;
}

void Schedule::run_in_order(World& world, const std::vector<bool>& enabled) {
  for (std::size_t k = 0; k < systems_.size(); ++k)
    if (enabled[k]) run_one(k, world);
}

std::vector<std::pair<std::size_t, std::size_t>> Schedule::edges() const {
  if (!graph_) build();
  return graph_->edges;
}

bool Schedule::sequential() const {
  if (!graph_) build();
  return graph_->chain;
}

}  // namespace granflow
