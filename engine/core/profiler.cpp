#include "engine/core/profiler.hpp"

#include <fmt/format.h>

namespace granflow {

std::size_t Profiler::register_system(const std::string& name) {
  std::lock_guard lock(mutex_);
  for (std::size_t k = 0; k < entries_.size(); ++k)
    if (entries_[k].system == name) return k;
  entries_.push_back(ProfileEntry{name});
  return entries_.size() - 1;
}

void Profiler::record(std::size_t slot, double seconds) {
  std::lock_guard lock(mutex_);
  entries_[slot].calls += 1;
  entries_[slot].total_seconds += seconds;
}

void Profiler::record_device(const ProfileEntry& entry) {
  const std::size_t slot = register_system(entry.system);
  std::lock_guard lock(mutex_);
  entries_[slot].calls += entry.calls;
  entries_[slot].total_seconds += entry.total_seconds;
}

std::vector<ProfileEntry> Profiler::entries() const {
  std::lock_guard lock(mutex_);
  return entries_;
}

std::string Profiler::table() const {
  const auto rows = entries();
  std::string out = fmt::format("{:<32} {:>10} {:>14} {:>14}\n", "system", "calls", "total [s]", "mean [s]");
  for (const auto& row : rows)
    out += fmt::format("{:<32} {:>10} {:>14.6f} {:>14.3e}\n", row.system, row.calls, row.total_seconds,
                       row.mean_seconds());
  return out;
}

}  // namespace granflow
