#pragma once
// Future-event calendar holding at most one event per particle, after Paul
// (J. Comput. Phys. 221, 615 (2007)): the current time bucket is a binary
// heap, later buckets of the current block are unsorted intrusive lists, and
// events beyond the block wait in an overflow list. Insert, remove and
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
  void rebuild(double now, const std::vector<double>& times);

  // Schedules particle i at time t, replacing any event it had. Infinite t unschedules.
  void schedule(std::uint32_t i, double t);
  void unschedule(std::uint32_t i);

  // Particle of the earliest event (ties: lowest index), or none.
  std::uint32_t earliest();
  double time_of(std::uint32_t i) const { return nodes_[i].time; }
  std::size_t size() const { return scheduled_; }

  double bucket_width() const { return width_; }
  std::size_t bytes_per_particle() const;

 private:
  static constexpr std::int32_t in_heap = -2;
  static constexpr std::int32_t in_overflow = -3;
  static constexpr std::int32_t nowhere = -1;

  void insert(std::uint32_t i);
  void remove(std::uint32_t i);
  void list_push(std::int32_t& head, std::uint32_t i);
  void list_erase(std::int32_t& head, std::uint32_t i);
  void overflow_erase(std::uint32_t i);
  bool heap_less(std::uint32_t a, std::uint32_t b) const {
    return nodes_[a].time < nodes_[b].time || (nodes_[a].time == nodes_[b].time && a < b);
  }
  void heap_push(std::uint32_t i);
  void heap_erase(std::uint32_t i);
  void sift_up(std::size_t position);
  void sift_down(std::size_t position);
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
  std::vector<std::uint32_t> overflow_;  // unordered; a member's Node::next is its position here
  std::vector<std::uint32_t> heap_;

  double block_start_ = 0.0;
  double width_ = 1.0;
  double inverse_width_ = 1.0;
  std::size_t current_ = 0;
  std::size_t scheduled_ = 0;
  std::uint64_t loaded_in_block_ = 0;  // events that passed through the heap this block
};

}  // namespace granflow::edmd
