#pragma once
// Future-event calendar holding at most one event per particle, after Paul
// (J. Comput. Phys. 221, 615 (2007)): the buckets of the current block are
// unsorted intrusive lists, the current one searched for its earliest event
// (Paul's tree is kept only for a bucket that holds many: a binary heap),
// and events beyond the block wait in an overflow list. Insert, remove and
// find-earliest are O(1) on average. The bucket width is retuned at every
// block from the measured event rate, so the calendar keeps a few events per
// bucket while a granular gas cools and its event rate falls by orders of
// magnitude.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace granflow::edmd {

class EventCalendar {
 public:
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

  explicit EventCalendar(std::size_t particle_count = 0);

  // Discards every event and sizes the bucket block for `times` (one per
  // particle, infinite = nothing scheduled), then schedules them.
  void rebuild(double now, const std::vector<double>& times) {
    rebuild(now, times.size(), [&](std::uint32_t i) { return times[i]; });
  }
  // The same with particle i's time from event_time(i), kept in the
  // calendar's own records rather than in a list of its own.
  template <class EventTime>
  void rebuild(double now, std::size_t count, EventTime&& event_time) {
    clear(count);
    for (std::uint32_t i = 0; i < count; ++i) nodes_[i].time = event_time(i);
    schedule_all(now);
  }

  // Schedules particle i at time t, replacing any event it had. Infinite t unschedules.
  void schedule(std::uint32_t i, double t);
  void unschedule(std::uint32_t i);

  // Particle of the earliest event (ties: lowest index), or none.
  std::uint32_t earliest() {
    return earliest([](std::uint32_t) {});
  }
  // The same, calling soon(k) for the particle k of every event in a bucket
  // as it becomes the current one: the events due within the next few,
  // whose data a caller may ask the memory for ahead of time. Each event is
  // passed once at most; those filed straight into the current bucket are
  // not (their particle has just been predicted, so its data is at hand).
  template <class Soon>
  std::uint32_t earliest(Soon&& soon) {
    if (!heap_.empty()) return heap_.front();
    const auto passed_over = [](std::uint32_t) {};
    std::int32_t first = bucket_head_[current_];
    if (first >= 0) return earliest_in_current(first, passed_over);
    first = first_of_later_buckets();
    if (first < 0) return none;
    return earliest_in_current(first, soon);
  }
  double time_of(std::uint32_t i) const { return nodes_[i].time; }
  std::size_t size() const { return scheduled_; }

  // Releases the memory of every event (see release_pages()); only
  // rebuild() may follow.
  void release_events() const;

  double bucket_width() const { return width_; }
  std::size_t bytes_per_particle() const;

 private:
  static constexpr std::int32_t in_heap = -2;
  static constexpr std::int32_t in_overflow = -3;
  static constexpr std::int32_t nowhere = -1;

  void clear(std::size_t count);
  void schedule_all(double now);
  std::int32_t first_of_later_buckets();
  template <class Soon>
  std::uint32_t earliest_in_current(std::int32_t first, const Soon& soon);
  std::uint32_t heap_current();
  void insert(std::uint32_t i);
  void file(std::uint32_t i);
  void remove(std::uint32_t i);
  void list_push(std::int32_t& head, std::uint32_t i);
  void list_erase(std::int32_t& head, std::uint32_t i);
  void overflow_erase(std::uint32_t i);
  // Time order, ties by particle index: a total order, so the earliest is
  // the same whether it is searched for or kept at a heap's root.
  bool earlier(std::uint32_t a, std::uint32_t b) const {
    return nodes_[a].time < nodes_[b].time || (nodes_[a].time == nodes_[b].time && a < b);
  }
  bool heap_less(std::uint32_t a, std::uint32_t b) const { return earlier(a, b); }
  void heap_push(std::uint32_t i);
  void heap_erase(std::uint32_t i);
  void sift_up(std::size_t position, std::uint32_t item);
  void sift_down(std::size_t position, std::uint32_t item);
  void heap_set(std::size_t position, std::uint32_t i) {
    heap_[position] = i;
    nodes_[i].next = static_cast<std::int32_t>(position);
  }
  void start_next_block();

  // One record per particle, so an event touches one cache line of the calendar.
  struct Node {
    double time;
    std::int32_t next;   // bucket list link, or position in the heap or overflow
    std::int32_t where;  // bucket index, in_heap, in_overflow or nowhere
  };
  std::vector<Node> nodes_;
  std::vector<std::int32_t> bucket_head_;
  // Unordered, its first overflow_size_ entries used; a member's Node::next is
  // its position here. Room for every particle is kept, so that a new block
  // can sort the overflow into buckets in place.
  std::vector<std::uint32_t> overflow_;
  std::size_t overflow_size_ = 0;
  // The current bucket's events while it holds many (more than heap_from
  // when searched), else empty: a bucket holds about three, and searching
  // them costs fewer instructions than keeping them in heap order.
  static constexpr std::size_t heap_from = 16;
  std::vector<std::uint32_t> heap_;

  double block_start_ = 0.0;
  double width_ = 1.0;
  double inverse_width_ = 1.0;
  std::size_t current_ = 0;
  // An event whose offset from the block start, in bucket widths, is below
  // current_end_ (current_ + 1) belongs in the current bucket, below bucket_count_ in a
  // bucket, else in the overflow; kept as doubles so that filing an event
  // compares its offset without rounding it or converting indices.
  double current_end_ = 1.0;
  double bucket_count_ = 1.0;
  std::size_t scheduled_ = 0;
  std::uint64_t loaded_in_block_ = 0;  // events that left the current bucket this block
};

// What every event does is defined here, so that the event loop inlines it.

inline void EventCalendar::schedule(std::uint32_t i, double t) {
  if (nodes_[i].where != nowhere) remove(i);
  nodes_[i].time = t;
  if (t < std::numeric_limits<double>::infinity()) insert(i);
}

inline void EventCalendar::insert(std::uint32_t i) {
  ++scheduled_;
  file(i);
}

// floor(offset) <= current_ exactly when offset < current_ + 1, and below
// bucket_count_ the truncated offset is its floor: the same buckets as
// rounding the offset, without doing it.
inline void EventCalendar::file(std::uint32_t i) {
  const double offset = (nodes_[i].time - block_start_) * inverse_width_;
  if (offset < current_end_) {
    if (!heap_.empty()) {
      heap_push(i);
    } else {
      nodes_[i].where = static_cast<std::int32_t>(current_);
      list_push(bucket_head_[current_], i);
    }
  } else if (offset < bucket_count_) {
    const auto k = static_cast<std::int32_t>(offset);
    nodes_[i].where = k;
    list_push(bucket_head_[static_cast<std::size_t>(k)], i);
  } else {
    nodes_[i].where = in_overflow;
    nodes_[i].next = static_cast<std::int32_t>(overflow_size_);
    overflow_[overflow_size_++] = i;
  }
}

inline void EventCalendar::remove(std::uint32_t i) {
  --scheduled_;
  const std::int32_t w = nodes_[i].where;
  if (w == in_heap) {
    heap_erase(i);
    ++loaded_in_block_;
  } else if (w == in_overflow) {
    overflow_erase(i);
  } else {
    list_erase(bucket_head_[static_cast<std::size_t>(w)], i);
    if (w == static_cast<std::int32_t>(current_)) ++loaded_in_block_;
  }
  nodes_[i].where = nowhere;
}

inline void EventCalendar::list_push(std::int32_t& head, std::uint32_t i) {
  nodes_[i].next = head;
  head = static_cast<std::int32_t>(i);
}

// Buckets hold a few events, so finding the predecessor by a walk is cheaper
// than keeping back links.
inline void EventCalendar::list_erase(std::int32_t& head, std::uint32_t i) {
  std::int32_t* link = &head;
  while (*link != static_cast<std::int32_t>(i)) link = &nodes_[static_cast<std::size_t>(*link)].next;
  *link = nodes_[i].next;
}

inline void EventCalendar::overflow_erase(std::uint32_t i) {
  const auto position = static_cast<std::size_t>(nodes_[i].next);
  const std::uint32_t last = overflow_[--overflow_size_];
  overflow_[position] = last;
  nodes_[last].next = static_cast<std::int32_t>(position);
}

// The earliest of the current bucket's list, which starts at `first`.
template <class Soon>
inline std::uint32_t EventCalendar::earliest_in_current(std::int32_t first, const Soon& soon) {
  auto best = static_cast<std::uint32_t>(first);
  soon(best);
  std::size_t seen = 1;
  for (std::int32_t k = nodes_[best].next; k >= 0; k = nodes_[static_cast<std::size_t>(k)].next, ++seen) {
    soon(static_cast<std::uint32_t>(k));
    if (earlier(static_cast<std::uint32_t>(k), best)) best = static_cast<std::uint32_t>(k);
  }
  return seen > heap_from ? heap_current() : best;
}

inline void EventCalendar::heap_push(std::uint32_t i) {
  nodes_[i].where = in_heap;
  heap_.push_back(i);
  sift_up(heap_.size() - 1, i);
}

// The hole left at `position` is filled by the last item, which moves up or
// down from there (most often the earliest event leaves and it moves down).
inline void EventCalendar::heap_erase(std::uint32_t i) {
  const auto position = static_cast<std::size_t>(nodes_[i].next);
  const std::uint32_t last = heap_.back();
  heap_.pop_back();
  if (position == heap_.size()) return;
  if (position > 0 && heap_less(last, heap_[(position - 1) / 2]))
    sift_up(position, last);
  else
    sift_down(position, last);
}

// Moves `item` from the hole at `position` towards the root to its place.
inline void EventCalendar::sift_up(std::size_t position, std::uint32_t item) {
  while (position > 0) {
    const std::size_t parent = (position - 1) / 2;
    if (!heap_less(item, heap_[parent])) break;
    heap_set(position, heap_[parent]);
    position = parent;
  }
  heap_set(position, item);
}

// Moves `item` from the hole at `position` towards the leaves to its place.
inline void EventCalendar::sift_down(std::size_t position, std::uint32_t item) {
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

}  // namespace granflow::edmd
