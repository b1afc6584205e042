#pragma once
// A sweep cut into N disjoint shards for job arrays (`granflow sweep FILE
// --shard I/N`): each run belongs to one shard, fixed by the sweep file and
// N alone, so every array task computes the same split without talking to
// the others. Runs are balanced by their expected cost where the sweep file
// gives one (`cost`: the keys whose product grows with a run's work), by
// count otherwise.

#include <cstddef>
#include <string>
#include <vector>

#include "engine/app/sweep_plan.hpp"

namespace granflow {

struct Shard {
  std::size_t index = 0;  // 1 .. count
  std::size_t count = 0;  // 0: the whole sweep
};

// "I/N" with 1 <= I <= N; ConfigError naming the text otherwise.
Shard parse_shard(const std::string& text);

// The shard (0-based) of every run of the plan: the longest-expected run
// first, each to the shard with the least expected work so far (ties: the
// lower shard); with equal costs, runs k, k + N, ... share a shard.
std::vector<std::size_t> shard_of_runs(const SweepPlan& plan, std::size_t count);

// Where a shard records that it has finished, and what each of its runs did.
std::string shard_record_name(std::size_t index, std::size_t count);

}  // namespace granflow
