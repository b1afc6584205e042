#pragma once
// Per-system wall-time accounting. Only the Schedule (the one place that runs
// systems) records into it, so systems never time themselves.

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace granflow {

struct ProfileEntry {
  std::string system;
  std::uint64_t calls = 0;
  double total_seconds = 0.0;
  double mean_seconds() const { return calls ? total_seconds / static_cast<double>(calls) : 0.0; }
};

class Profiler {
 public:
  static constexpr const char* key = "profiler";

  // Returns a slot index; registration order is the table order.
  std::size_t register_system(const std::string& name);
  void record(std::size_t slot, double seconds);
  // Adds calls and time an accelerator's own clock measured for a stage
  // (named system/stage), summed into any earlier entry of that name.
  void record_device(const ProfileEntry& entry);
  std::vector<ProfileEntry> entries() const;
  std::string table() const;

 private:
  mutable std::mutex mutex_;
  std::vector<ProfileEntry> entries_;
};

class ScopedTimer {
 public:
  ScopedTimer(Profiler& profiler, std::size_t slot)
      : profiler_(profiler), slot_(slot), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    const auto elapsed = std::chrono::steady_clock::now() - start_;
    profiler_.record(slot_, std::chrono::duration<double>(elapsed).count());
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  Profiler& profiler_;
  std::size_t slot_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace granflow
