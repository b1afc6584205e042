#include "engine/app/sweep_shards.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <functional>
#include <numeric>
#include <queue>
#include <utility>

#include "engine/core/config.hpp"

namespace granflow {

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  const auto number = [&](std::size_t from, std::size_t to, std::size_t& out) {
    const char* begin = text.data() + from;
    const char* end = text.data() + to;
    const auto [last, error] = std::from_chars(begin, end, out);
    return from < to && error == std::errc{} && last == end;
  };
  Shard shard;
  if (slash == std::string::npos || !number(0, slash, shard.index) || !number(slash + 1, text.size(), shard.count) ||
      shard.count == 0 || shard.index == 0 || shard.index > shard.count || shard.count > 100000)
    throw ConfigError(fmt::format("--shard '{}': expected I/N with 1 <= I <= N <= 100000 (e.g. 2/8 for the second "
                                  "of eight shards)",
                                  text));
  return shard;
}

std::vector<std::size_t> shard_of_runs(const SweepPlan& plan, std::size_t count) {
  const std::size_t runs = plan.runs.size();
  std::vector<std::size_t> order(runs);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return plan.runs[a].cost > plan.runs[b].cost; });
  // The least loaded shard (the lowest-numbered among equals) by a heap:
  // a million runs over 10^5 shards in seconds, not a scan of every shard
  // for every run.
  using Load = std::pair<double, std::size_t>;
  std::priority_queue<Load, std::vector<Load>, std::greater<>> least;
  for (std::size_t s = 0; s < count; ++s) least.emplace(0.0, s);
  std::vector<std::size_t> shard(runs, 0);
  for (const std::size_t k : order) {
    auto [load, s] = least.top();
    least.pop();
    shard[k] = s;
    least.emplace(load + plan.runs[k].cost, s);
  }
  return shard;
}

std::string shard_record_name(std::size_t index, std::size_t count) {
  return fmt::format("shard_{}_of_{}.txt", index, count);
}

}  // namespace granflow
