// The Schedule derives its graph from declared (typed) accesses only, runs
// independent systems concurrently, runs a dependent chain as a plain loop,
// skips disabled systems, and the Profiler counts every call.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>

#include "engine/core/schedule.hpp"
#include "engine/core/world.hpp"

namespace granflow {
namespace {

struct Pos : Column<double> {
  static constexpr const char* key = "pos";
};
struct Vel : Column<double> {
  static constexpr const char* key = "vel";
};
struct MassColumn : Column<double> {
  static constexpr const char* key = "mass";
};
struct FileResource {
  static constexpr const char* key = "file";
};

class Probe : public System {
 public:
  Probe(std::string name, Access access, std::vector<std::string>& log, std::mutex& mutex)
      : name_(std::move(name)), access_(std::move(access)), log_(log), mutex_(mutex) {}
  std::string name() const override { return name_; }
  Access access() const override { return access_; }
  void run(World&) override {
    std::lock_guard lock(mutex_);
    log_.push_back(name_);
  }

 private:
  std::string name_;
  Access access_;
  std::vector<std::string>& log_;
  std::mutex& mutex_;
};

TEST(Schedule, EdgesFollowDeclaredAccesses) {
  Profiler profiler;
  Schedule schedule(profiler);
  std::vector<std::string> log;
  std::mutex mutex;
  schedule.emplace<Probe>("advance", Access{}.writes<Pos, Vel>(), log, mutex);                        // 0
  schedule.emplace<Probe>("energy", Access{}.reads<Vel>().writes_observable("energy"), log, mutex);   // 1
  schedule.emplace<Probe>("density", Access{}.reads<Pos>().writes_observable("density"), log, mutex); // 2
  schedule.emplace<Probe>("writer",
                          Access{}.reads_observable("energy").reads_observable("density").writes<FileResource>(), log,
                          mutex);
  const auto edges = schedule.edges();
  const std::vector<std::pair<std::size_t, std::size_t>> expected{{0, 1}, {0, 2}, {2, 3}, {1, 3}};
  EXPECT_EQ(std::set(edges.begin(), edges.end()), std::set(expected.begin(), expected.end()));
  EXPECT_FALSE(schedule.sequential());

  World world;
  for (int k = 0; k < 3; ++k) schedule.run(world);
  ASSERT_EQ(log.size(), 12u);
  for (std::size_t k = 0; k < 12; k += 4) {
    EXPECT_EQ(log[k], "advance");
    EXPECT_EQ(log[k + 3], "writer");
  }
  for (const auto& entry : profiler.entries()) EXPECT_EQ(entry.calls, 3u) << entry.system;
}

TEST(Schedule, TransitiveEdgesAreNotRepeatedAndAChainRunsSequentially) {
  Profiler profiler;
  Schedule schedule(profiler);
  std::vector<std::string> log;
  std::mutex mutex;
  schedule.emplace<Probe>("a", Access{}.writes<Pos>(), log, mutex);
  schedule.emplace<Probe>("b", Access{}.reads<Pos>().writes<Vel>(), log, mutex);
  schedule.emplace<Probe>("c", Access{}.reads<Pos, Vel>(), log, mutex);
  EXPECT_EQ(schedule.edges().size(), 2u);  // a->b, b->c; a->c is implied
  EXPECT_TRUE(schedule.sequential());
  World world;
  schedule.run(world, {true, false, true});
  EXPECT_EQ(log, (std::vector<std::string>{"a", "c"}));
  for (const auto& entry : profiler.entries()) EXPECT_EQ(entry.calls, entry.system == "b" ? 0u : 1u) << entry.system;
}

TEST(Schedule, ReorderingParticlesConflictsWithEveryColumnButNoResource) {
  const Access resort = Access{}.writes_every_component();
  EXPECT_TRUE(accesses_conflict(resort, Access{}.reads<MassColumn>()));
  EXPECT_FALSE(accesses_conflict(resort, Access{}.reads<FileResource>()));
  EXPECT_FALSE(accesses_conflict(resort, Access{}.writes_observable("energy")));
  // Different observables of one store do not conflict; the same one does.
  EXPECT_FALSE(accesses_conflict(Access{}.writes_observable("a"), Access{}.writes_observable("b")));
  EXPECT_TRUE(accesses_conflict(Access{}.writes_observable("a"), Access{}.reads_observable("a")));
  EXPECT_FALSE(accesses_conflict(Access{}.reads<Pos>(), Access{}.reads<Pos>()));
}

class Sleeper : public System {
 public:
  Sleeper(std::string name, std::atomic<int>& running, std::atomic<int>& peak)
      : name_(std::move(name)), running_(running), peak_(peak) {}
  std::string name() const override { return name_; }
  Access access() const override { return Access{}.reads<Pos>().writes_observable(name_); }
  void run(World&) override {
    const int now = ++running_;
    int seen = peak_.load();
    while (now > seen && !peak_.compare_exchange_weak(seen, now)) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    --running_;
  }

 private:
  std::string name_;
  std::atomic<int>& running_;
  std::atomic<int>& peak_;
};

TEST(Schedule, IndependentSystemsRunConcurrently) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "needs two cores";
  Profiler profiler;
  Schedule schedule(profiler);
  std::atomic<int> running{0}, peak{0};
  schedule.emplace<Sleeper>("one", running, peak);
  schedule.emplace<Sleeper>("two", running, peak);
  EXPECT_TRUE(schedule.edges().empty());
  World world;
  schedule.run(world);
  EXPECT_EQ(peak.load(), 2);
}

TEST(World, PermuteReordersEveryColumnAndTellsListeners) {
  World world(3);
  world.add_component<Pos>().values = {0.0, 1.0, 2.0};
  std::vector<std::uint32_t> seen;
  world.on_permute([&](const std::vector<std::uint32_t>& order) { seen = order; });
  world.permute({2, 0, 1});
  EXPECT_EQ(world.component<Pos>().values, (std::vector<double>{2.0, 0.0, 1.0}));
  EXPECT_EQ(seen, (std::vector<std::uint32_t>{2, 0, 1}));
}

TEST(World, RestoredColumnsBecomeTypedWhenAskedForAndAreNeverDropped) {
  World saved(2);
  saved.add_component<Pos>().values = {0.5, 1.5};
  saved.add_component<Vel>().values = {-1.0, 2.0};
  const StateMap columns = saved.save_columns();
  World restored;
  restored.restore_columns(2, columns);
  EXPECT_TRUE(restored.has_component<Vel>());
  EXPECT_EQ(restored.component<Pos>().values, (std::vector<double>{0.5, 1.5}));
  // Vel was never asked for: it follows a permutation untyped and is saved again.
  restored.permute({1, 0});
  const StateMap again = restored.save_columns();
  EXPECT_EQ(again.at("vel"), (std::vector<double>{2.0, -1.0}));
  EXPECT_EQ(restored.component<Vel>().values, (std::vector<double>{2.0, -1.0}));
  EXPECT_THROW(restored.restore_columns(3, columns), std::invalid_argument);
}

}  // namespace
}  // namespace granflow
