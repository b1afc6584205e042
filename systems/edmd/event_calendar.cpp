#include "systems/edmd/event_calendar.hpp"

#include "engine/core/page_release.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace granflow::edmd {

namespace {
// Few events per bucket keep the search of the current one short; more
// would cost longer searches, fewer would cost empty-bucket scans.
constexpr double events_per_bucket = 3.0;
}  // namespace

EventCalendar::EventCalendar(std::size_t particle_count) {
  rebuild(0.0, std::vector<double>(particle_count, std::numeric_limits<double>::infinity()));
}

std::size_t EventCalendar::bytes_per_particle() const {
  const std::size_t count = std::max<std::size_t>(nodes_.size(), 1);
  return sizeof(Node) + ((bucket_head_.size() + overflow_.size()) * sizeof(std::int32_t)) / count;
}

void EventCalendar::clear(std::size_t count) {
  nodes_.assign(count, Node{std::numeric_limits<double>::infinity(), -1, nowhere});
  heap_.clear();
  overflow_.assign(count, 0);
  overflow_size_ = 0;
  scheduled_ = 0;
  // Two bucket heads per particle (8 bytes): a block spans about six events
  // per particle, so the events waiting in the overflow are re-filed at
  // fewer block starts than with half a head per particle, which cost more
  // instructions and time per event (docs/performance.md).
  const std::size_t buckets = std::max<std::size_t>(2 * count, 64);
  bucket_head_.assign(buckets, -1);
  bucket_count_ = static_cast<double>(buckets);
}

// Sizes the bucket block for the times in the nodes, then files them.
void EventCalendar::schedule_all(double now) {
  const std::size_t count = nodes_.size();
  double ahead = 0.0;
  std::size_t finite = 0;
  for (const Node& node : nodes_)
    if (const double t = node.time; std::isfinite(t)) {
      ahead += std::max(t - now, 0.0);
      ++finite;
    }
  // One event per particle lies on average `ahead/finite` in the future; a
  // block of twice that holds most of them and the overflow stays small.
  const double mean_ahead = finite ? ahead / static_cast<double>(finite) : 1.0;
  width_ = mean_ahead > 0.0 ? 2.0 * mean_ahead / bucket_count_ : 1.0;
  inverse_width_ = 1.0 / width_;
  block_start_ = now;
  current_ = 0;
  current_end_ = 1.0;
  loaded_in_block_ = 0;
  for (std::uint32_t i = 0; i < count; ++i) schedule(i, nodes_[i].time);
}

void EventCalendar::release_events() const {
  release_pages(nodes_);
  release_pages(overflow_);
  release_pages(bucket_head_);
}

void EventCalendar::unschedule(std::uint32_t i) {
  if (nodes_[i].where != nowhere) remove(i);
  nodes_[i].time = std::numeric_limits<double>::infinity();
}

// At the end of a block every event left is in the overflow. Those that fall
// in the new block are filed in its buckets and the rest stay, compacted in
// place: filing never writes beyond the entry being read.
void EventCalendar::start_next_block() {
  const double span = width_ * bucket_count_;
  const double block_end = block_start_ + span;
  // Retune: aim for a few events per bucket at the event rate just seen.
  if (loaded_in_block_ > 0) width_ = events_per_bucket * span / static_cast<double>(loaded_in_block_);
  else width_ = span;  // nothing happened in a whole block: widen fast
  inverse_width_ = 1.0 / width_;
  block_start_ = block_end;
  current_ = 0;
  current_end_ = 1.0;
  loaded_in_block_ = 0;

  const std::size_t pending = overflow_size_;
  double earliest_pending = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < pending; ++k) earliest_pending = std::min(earliest_pending, nodes_[overflow_[k]].time);
  // Skip empty stretches of time in one jump instead of block by block.
  if (earliest_pending > block_start_ + width_ * bucket_count_) block_start_ = earliest_pending;
  overflow_size_ = 0;
  for (std::size_t k = 0; k < pending; ++k) file(overflow_[k]);
}

std::int32_t EventCalendar::first_of_later_buckets() {
  if (scheduled_ == 0) return -1;
  while (bucket_head_[current_] < 0) {
    if (current_ + 1 < bucket_head_.size()) {
      ++current_;
      current_end_ += 1.0;
    } else {
      start_next_block();
    }
  }
  return bucket_head_[current_];
}

// A bucket of many events (a burst of equal times, say) is kept in heap
// order until it is spent, so that each event costs a logarithm of them
// rather than a search through all.
std::uint32_t EventCalendar::heap_current() {
  std::int32_t k = std::exchange(bucket_head_[current_], -1);
  while (k >= 0) {
    const auto i = static_cast<std::uint32_t>(k);
    k = nodes_[i].next;
    heap_push(i);
  }
  return heap_.front();
}

}  // namespace granflow::edmd
