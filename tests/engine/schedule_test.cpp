// The Schedule derives its graph from declared accesses only, runs
// independent systems concurrently, and the Profiler counts every call.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "engine/schedule.hpp"
#include "engine/world.hpp"

namespace granflow {
namespace {

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
  schedule.emplace<Probe>("advance", Access{{}, {"position", "velocity"}}, log, mutex);          // 0
  schedule.emplace<Probe>("energy", Access{{"velocity"}, {"observable:energy"}}, log, mutex);   // 1
  schedule.emplace<Probe>("density", Access{{"position"}, {"observable:density"}}, log, mutex);  // 2
  schedule.emplace<Probe>("writer", Access{{"observable:energy", "observable:density"}, {"file"}}, log, mutex);
  const auto edges = schedule.edges();
  const std::vector<std::pair<std::size_t, std::size_t>> expected{{0, 1}, {0, 2}, {2, 3}, {1, 3}};
  EXPECT_EQ(std::set(edges.begin(), edges.end()), std::set(expected.begin(), expected.end()));

  World world;
  for (int k = 0; k < 3; ++k) schedule.run(world);
  ASSERT_EQ(log.size(), 12u);
  for (std::size_t k = 0; k < 12; k += 4) {
    EXPECT_EQ(log[k], "advance");
    EXPECT_EQ(log[k + 3], "writer");
  }
  for (const auto& entry : profiler.entries()) EXPECT_EQ(entry.calls, 3u) << entry.system;
}

TEST(Schedule, TransitiveEdgesAreNotRepeated) {
  Profiler profiler;
  Schedule schedule(profiler);
  std::vector<std::string> log;
  std::mutex mutex;
  schedule.emplace<Probe>("a", Access{{}, {"x"}}, log, mutex);
  schedule.emplace<Probe>("b", Access{{"x"}, {"y"}}, log, mutex);
  schedule.emplace<Probe>("c", Access{{"x", "y"}, {}}, log, mutex);
  const auto edges = schedule.edges();
  EXPECT_EQ(edges.size(), 2u);  // a->b, b->c; a->c is implied
}

class Sleeper : public System {
 public:
  Sleeper(std::string name, std::atomic<int>& running, std::atomic<int>& peak)
      : name_(std::move(name)), running_(running), peak_(peak) {}
  std::string name() const override { return name_; }
  Access access() const override { return {{"shared_input"}, {"own:" + name_}}; }
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

}  // namespace
}  // namespace granflow
