#include "engine/schedule.hpp"

#include <algorithm>
#include <tbb/flow_graph.h>

namespace granflow {

namespace {
bool contains(const std::vector<std::string>& keys, const std::string& key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}
bool writes_touch(const Access& writer, const Access& other) {
  for (const auto& key : writer.writes)
    if (contains(other.reads, key) || contains(other.writes, key)) return true;
  return false;
}
}  // namespace

bool accesses_conflict(const Access& a, const Access& b) { return writes_touch(a, b) || writes_touch(b, a); }

struct Schedule::Graph {
  tbb::flow::graph graph;
  tbb::flow::broadcast_node<tbb::flow::continue_msg> start{graph};
  std::vector<std::unique_ptr<tbb::flow::continue_node<tbb::flow::continue_msg>>> nodes;
  std::vector<std::pair<std::size_t, std::size_t>> edges;
};

Schedule::Schedule(Profiler& profiler) : profiler_(profiler) {}
Schedule::~Schedule() = default;

System& Schedule::add(std::unique_ptr<System> system) {
  profile_slots_.push_back(profiler_.register_system(system->name()));
  systems_.push_back(std::move(system));
  graph_.reset();
  return *systems_.back();
}

void Schedule::build() {
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

  for (std::size_t k = 0; k < count; ++k) {
    graph_->nodes.push_back(std::make_unique<tbb::flow::continue_node<tbb::flow::continue_msg>>(
        graph_->graph, [this, k](const tbb::flow::continue_msg&) {
          ScopedTimer timer(profiler_, profile_slots_[k]);
          systems_[k]->run(*current_world_);
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

void Schedule::run(World& world) {
  if (!graph_) build();
  current_world_ = &world;
  graph_->start.try_put(tbb::flow::continue_msg{});
  graph_->graph.wait_for_all();
  current_world_ = nullptr;
}

std::vector<std::pair<std::size_t, std::size_t>> Schedule::edges() const {
  if (!graph_) const_cast<Schedule*>(this)->build();
  return graph_->edges;
}

}  // namespace granflow
