#pragma once
// The wall time of each part of a step that one system spreads over MPI
// ranks, for the /profile table: this rank's as rows `<step>.<part>` (rank
// 0's reach the file), and every rank's as rows `<step>.rank<r>.<part>`, so
// that a slow rank, and the others' wait for it in the communication, show.

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/communicator.hpp"
#include "engine/core/profiler.hpp"

namespace granflow {

template <std::size_t Parts>
class PhaseTimes {
 public:
  explicit PhaseTimes(const std::array<const char*, Parts>& names) : names_(names) {}

  template <class Work>
  void timed(std::size_t part, Work&& work) {
    const auto start = std::chrono::steady_clock::now();
    std::forward<Work>(work)();
    seconds_[part] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++calls_[part];
  }

  // Collective: every rank's times travel to every rank.
  std::vector<ProfileEntry> entries(const std::string& step, const Communicator& ranks) const {
    std::vector<ProfileEntry> out;
    for (std::size_t k = 0; k < Parts; ++k) out.push_back({step + "." + names_[k], calls_[k], seconds_[k]});
    std::vector<double> mine(2 * Parts);
    for (std::size_t k = 0; k < Parts; ++k) {
      mine[2 * k] = static_cast<double>(calls_[k]);
      mine[2 * k + 1] = seconds_[k];
    }
    const std::vector<double> all = ranks.gather_all(mine);
    for (std::size_t r = 0; (r + 1) * mine.size() <= all.size(); ++r)
      for (std::size_t k = 0; k < Parts; ++k)
        out.push_back({fmt::format("{}.rank{}.{}", step, r, names_[k]),
                       static_cast<std::uint64_t>(all[r * mine.size() + 2 * k]), all[r * mine.size() + 2 * k + 1]});
    return out;
  }

 private:
  std::array<const char*, Parts> names_;
  std::array<double, Parts> seconds_{};
  std::array<std::uint64_t, Parts> calls_{};
};

}  // namespace granflow
