#pragma once
// The soft spheres cut into one contiguous domain per thread, the same
// domains in every pass of a step (kicks, drift, skin test, gravity, walls,
// pairs), each domain worked through by the same thread whenever that
// thread keeps up. On two cores a pass over spheres whose cache lines the other core
// wrote last runs at a third of the speed of one over its own (the second
// half-kick of the 10 580-sphere bed: 60 us against 20 us), so which
// thread touches which sphere decides the speed-up more than the balance
// of the work. The domains decide only who does the work, never the order
// of a sum: results do not depend on them or on the thread count.

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace granflow::dem {

// Domain d holds the slabs [slab[d], slab[d + 1]) of the neighbour lists
// and the spheres of ranks [sphere[d], sphere[d + 1]).
struct ThreadDomains {
  std::vector<std::uint32_t> slab;
  std::vector<std::uint32_t> sphere;
  // The spheres they were made for: all of them are some domain's, but for
  // the copies of other ranks' spheres a rank of a system spread over MPI
  // ranks holds and does not move (dem_domain_step.hpp).
  std::size_t spheres = 0;

  std::size_t count() const { return sphere.empty() ? 0 : sphere.size() - 1; }
  bool covers(std::size_t n) const { return count() > 0 && spheres == n; }
};

// The spheres 0 .. n - 1 in `threads` equal runs (before lists exist).
inline ThreadDomains even_domains(std::size_t n, std::size_t threads) {
  threads = std::max<std::size_t>(1, threads);
  ThreadDomains d;
  d.sphere.resize(threads + 1);
  for (std::size_t k = 0; k <= threads; ++k) d.sphere[k] = static_cast<std::uint32_t>(n * k / threads);
  d.spheres = n;
  return d;
}

// Whole slabs per domain, balanced by a cost of one per listed pair and
// two per sphere (the per-sphere passes of a step cost about as much as
// two pairs, measured on the vibrated bed). slabs[s] is the first rank of
// slab s, offsets[m] the first pair of rank m.
inline ThreadDomains balanced_domains(const std::vector<std::uint32_t>& slabs, const std::vector<std::uint32_t>& offsets,
                                      std::size_t threads) {
  threads = std::max<std::size_t>(1, threads);
  const std::size_t count = slabs.size() - 1;
  const auto cost = [&](std::size_t s) {
    return static_cast<double>(offsets[slabs[s]]) + 2.0 * static_cast<double>(slabs[s]);
  };
  const double total = cost(count);
  ThreadDomains d;
  d.slab.assign(threads + 1, static_cast<std::uint32_t>(count));
  d.slab[0] = 0;
  std::size_t s = 0;
  for (std::size_t k = 1; k < threads; ++k) {
    const double target = total * static_cast<double>(k) / static_cast<double>(threads);
    while (s < count && cost(s + 1) <= target) ++s;
    // The nearer of the two slab edges around the target.
    if (s < count && cost(s + 1) - target < target - cost(s)) ++s;
    d.slab[k] = static_cast<std::uint32_t>(std::max<std::size_t>(s, d.slab[k - 1]));
  }
  d.sphere.resize(threads + 1);
  for (std::size_t k = 0; k <= threads; ++k) d.sphere[k] = slabs[d.slab[k]];
  d.spheres = slabs.back();
  return d;
}

// body(d, k) for every piece k < pieces[d] of every domain d, in parallel.
// A thread works through the domain of its own arena slot from the front,
// then takes what is left of the others from the back: a slow core (two
// virtual cores do not always run alike) is helped, and most pieces stay
// with their owner.
template <class Body>
void for_each_piece(const std::vector<std::size_t>& pieces, const Body& body) {
  const std::size_t count = pieces.size();
  if (count == 0) return;
  if (count == 1) {
    for (std::size_t k = 0; k < pieces[0]; ++k) body(std::size_t{0}, k);
    return;
  }
  // Per domain: the next piece from the front (high half) and one past the
  // last from the back (low half), claimed together.
  struct alignas(64) Claim {
    std::atomic<std::uint64_t> range;
  };
  const std::unique_ptr<Claim[]> claims(new Claim[count]);
  for (std::size_t d = 0; d < count; ++d) claims[d].range.store(pieces[d], std::memory_order_relaxed);
  const auto take = [&](std::size_t d, bool front, std::size_t& k) {
    std::uint64_t now = claims[d].range.load(std::memory_order_relaxed);
    for (;;) {
      const std::uint64_t next = now >> 32, end = now & 0xffffffffu;
      if (next >= end) return false;
      const std::uint64_t want = front ? ((next + 1) << 32) | end : (next << 32) | (end - 1);
      if (claims[d].range.compare_exchange_weak(now, want, std::memory_order_relaxed)) {
        k = static_cast<std::size_t>(front ? next : end - 1);
        return true;
      }
    }
  };
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, count, 1),
      [&](const tbb::blocked_range<std::size_t>& tasks) {
        for (std::size_t task = tasks.begin(); task != tasks.end(); ++task) {
          const int slot = tbb::this_task_arena::current_thread_index();
          const std::size_t own = slot >= 0 ? static_cast<std::size_t>(slot) : count;
          std::size_t k;
          if (own < count)
            while (take(own, true, k)) body(own, k);
          for (std::size_t d = 0; d < count; ++d)
            if (d != own)
              while (take(d, false, k)) body(d, k);
        }
      },
      tbb::static_partitioner{});
}

// body(d, from, to) over every domain's spheres, a run of at most `run` at a time.
template <class Body>
void for_each_sphere_run(const ThreadDomains& domains, const Body& body, std::size_t run = 512) {
  std::vector<std::size_t> pieces(domains.count());
  for (std::size_t d = 0; d < pieces.size(); ++d) pieces[d] = (domains.sphere[d + 1] - domains.sphere[d] + run - 1) / run;
  for_each_piece(pieces, [&](std::size_t d, std::size_t k) {
    const std::size_t from = domains.sphere[d] + k * run;
    body(d, from, std::min<std::size_t>(from + run, domains.sphere[d + 1]));
  });
}

// The threads a pass may use: the arena's, capped by a global limit
// (--threads). A domain for a thread that cannot exist would be handed to a
// slot nobody serves: oneTBB's static partitioner then leaves its affinity
// proxies behind, a few hundred bytes every pass, for the whole run.
inline std::size_t domain_threads() {
  const std::size_t arena = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const std::size_t allowed = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return std::max<std::size_t>(1, std::min(arena, allowed));
}

}  // namespace granflow::dem
