#include "systems/edmd/event_calendar.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace granflow::edmd {

namespace {
// Few events per bucket keep the heap tiny; more would cost heap work,
// fewer would cost empty-bucket scans.
constexpr double events_per_bucket = 3.0;
}  // namespace

EventCalendar::EventCalendar(std::size_t particle_count) {
  rebuild(0.0, std::vector<double>(particle_count, std::numeric_limits<double>::infinity()));
}

std::size_t EventCalendar::bytes_per_particle() const {
  const std::size_t count = std::max<std::size_t>(nodes_.size(), 1);
  return sizeof(Node) + ((bucket_head_.size() + overflow_.capacity()) * sizeof(std::int32_t)) / count;
}

void EventCalendar::rebuild(double now, const std::vector<double>& times) {
  const std::size_t count = times.size();
  nodes_.assign(count, Node{std::numeric_limits<double>::infinity(), -1, nowhere});
  heap_.clear();
  overflow_.clear();
  scheduled_ = 0;
  // Half a bucket head per particle keeps the calendar at ~22 bytes per particle.
  const std::size_t buckets = std::max<std::size_t>(count / 2, 64);
  bucket_head_.assign(buckets, -1);

  double ahead = 0.0;
  std::size_t finite = 0;
  for (double t : times)
    if (std::isfinite(t)) {
      ahead += std::max(t - now, 0.0);
      ++finite;
    }
  // One event per particle lies on average `ahead/finite` in the future; a
  // block of twice that holds most of them and the overflow stays small.
  const double mean_ahead = finite ? ahead / static_cast<double>(finite) : 1.0;
  width_ = mean_ahead > 0.0 ? 2.0 * mean_ahead / static_cast<double>(buckets) : 1.0;
  inverse_width_ = 1.0 / width_;
  block_start_ = now;
  current_ = 0;
  loaded_in_block_ = 0;
  for (std::uint32_t i = 0; i < count; ++i) schedule(i, times[i]);
}

void EventCalendar::schedule(std::uint32_t i, double t) {
  if (nodes_[i].where != nowhere) remove(i);
  nodes_[i].time = t;
  if (std::isfinite(t)) insert(i);
}

void EventCalendar::unschedule(std::uint32_t i) {
  if (nodes_[i].where != nowhere) remove(i);
  nodes_[i].time = std::numeric_limits<double>::infinity();
}

void EventCalendar::insert(std::uint32_t i) {
  ++scheduled_;
  const double bucket = std::floor((nodes_[i].time - block_start_) * inverse_width_);
  if (bucket <= static_cast<double>(current_)) {
    heap_push(i);
  } else if (bucket < static_cast<double>(bucket_head_.size())) {
    const auto k = static_cast<std::int32_t>(bucket);
    nodes_[i].where = k;
    list_push(bucket_head_[static_cast<std::size_t>(k)], i);
  } else {
    nodes_[i].where = in_overflow;
    nodes_[i].next = static_cast<std::int32_t>(overflow_.size());
    overflow_.push_back(i);
  }
}

void EventCalendar::remove(std::uint32_t i) {
  --scheduled_;
  const std::int32_t w = nodes_[i].where;
  if (w == in_heap)
    heap_erase(i);
  else if (w == in_overflow)
    overflow_erase(i);
  else
    list_erase(bucket_head_[static_cast<std::size_t>(w)], i);
  nodes_[i].where = nowhere;
}

void EventCalendar::list_push(std::int32_t& head, std::uint32_t i) {
  nodes_[i].next = head;
  head = static_cast<std::int32_t>(i);
}

// Buckets hold a few events, so finding the predecessor by a walk is cheaper
// than keeping back links.
void EventCalendar::list_erase(std::int32_t& head, std::uint32_t i) {
  std::int32_t* link = &head;
  while (*link != static_cast<std::int32_t>(i)) link = &nodes_[static_cast<std::size_t>(*link)].next;
  *link = nodes_[i].next;
}

void EventCalendar::overflow_erase(std::uint32_t i) {
  const auto position = static_cast<std::size_t>(nodes_[i].next);
  const std::uint32_t last = overflow_.back();
  overflow_[position] = last;
  nodes_[last].next = static_cast<std::int32_t>(position);
  overflow_.pop_back();
}

void EventCalendar::heap_push(std::uint32_t i) {
  nodes_[i].where = in_heap;
  ++loaded_in_block_;
  heap_.push_back(i);
  heap_set(heap_.size() - 1, i);
  sift_up(heap_.size() - 1);
}

void EventCalendar::heap_erase(std::uint32_t i) {
  const auto position = static_cast<std::size_t>(nodes_[i].next);
  const std::uint32_t last = heap_.back();
  heap_.pop_back();
  if (position == heap_.size()) return;
  heap_set(position, last);
  sift_up(position);
  sift_down(static_cast<std::size_t>(nodes_[last].next));
}

void EventCalendar::sift_up(std::size_t position) {
  const std::uint32_t item = heap_[position];
  while (position > 0) {
    const std::size_t parent = (position - 1) / 2;
    if (!heap_less(item, heap_[parent])) break;
    heap_set(position, heap_[parent]);
    position = parent;
  }
  heap_set(position, item);
}

void EventCalendar::sift_down(std::size_t position) {
  const std::uint32_t item = heap_[position];
  const std::size_t count = heap_.size();
  while (true) {
    std::size_t child = 2 * position + 1;
    if (child >= count) break;
    if (child + 1 < count && heap_less(heap_[child + 1], heap_[child])) ++child;
    if (!heap_less(heap_[child], item)) break;
    heap_set(position, heap_[child]);
    position = child;
  }
  heap_set(position, item);
}

void EventCalendar::start_next_block() {
  const double span = width_ * static_cast<double>(bucket_head_.size());
  const double block_end = block_start_ + span;
  // Retune: aim for a few events per bucket at the event rate just seen.
  if (loaded_in_block_ > 0) width_ = events_per_bucket * span / static_cast<double>(loaded_in_block_);
  else width_ = span;  // nothing happened in a whole block: widen fast
  inverse_width_ = 1.0 / width_;
  block_start_ = block_end;
  current_ = 0;
  loaded_in_block_ = 0;

  std::vector<std::uint32_t> pending;
  pending.swap(overflow_);
  double earliest_pending = std::numeric_limits<double>::infinity();
  for (std::uint32_t i : pending) earliest_pending = std::min(earliest_pending, nodes_[i].time);
  // Skip empty stretches of time in one jump instead of block by block.
  if (earliest_pending > block_start_ + width_ * static_cast<double>(bucket_head_.size()))
    block_start_ = earliest_pending;
  for (std::uint32_t i : pending) {
    nodes_[i].where = nowhere;
    --scheduled_;
    insert(i);
  }
  overflow_.reserve(pending.capacity());
}

std::uint32_t EventCalendar::earliest() {
  if (scheduled_ == 0) return none;
  while (heap_.empty()) {
    if (current_ + 1 < bucket_head_.size()) {
      ++current_;
      std::int32_t k = std::exchange(bucket_head_[current_], -1);
      while (k >= 0) {
        const auto i = static_cast<std::uint32_t>(k);
        k = nodes_[i].next;
        heap_push(i);
      }
    } else {
      start_next_block();
    }
  }
  return heap_.front();
}

}  // namespace granflow::edmd
