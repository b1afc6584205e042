#pragma once
// The candidate partners of one prediction: where their motion records lie
// (offsets in doubles from the first record, so that the contact test loads a
// record with one addressing mode, no arithmetic), in the order the cell lists
// were walked, and for each the periodic image it is seen through (an offset
// into the grid's table of shifts). The contact test loads the records
// itself, so a candidate costs the walk two stores instead of a copy of its
// record, and a candidate that both particles of a collision see is listed
// once and tested by both (each over its own range).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "systems/edmd/motion_record.hpp"

namespace granflow::edmd {

class CandidateList {
 public:
  // The contact test runs over whole groups of `group` candidates, so that it
  // needs no remainder loop: testing a particle of the list outside a range
  // does no harm (it is a real particle, in cells too far away to be reached
  // before a cell crossing), and Writer::close() fills the rest of the last
  // group with the sentinel, a record no test accepts.
  static constexpr std::size_t group = 4;

  CandidateList() { grow(); }

  // Record offsets are 32-bit: a gas may hold up to this many particles.
  template <int D>
  static constexpr std::size_t max_records = (std::size_t{1} << 32) / MotionRecord<D>::stride;

  std::size_t size() const { return size_; }
  // Each candidate's record offset, in doubles.
  const std::uint32_t* record_offsets() const { return offset_.data(); }
  // Offsets, in doubles, of each candidate's periodic shift in the shift
  // table, where the list was written with shifts.
  const std::int32_t* shift_offsets() const { return shift_.data(); }
  // Particle index of candidate c, in a list of records of D dimensions.
  template <int D>
  std::uint32_t index(std::size_t c) const {
    return offset_[c] / static_cast<std::uint32_t>(MotionRecord<D>::stride);
  }
  // Room for one contact time per candidate, the last group whole.
  double* times() { return times_.data(); }

  // Appends candidates cell list by cell list. Each candidate's record is
  // prefetched as it is listed, so that the records of all candidates come
  // from memory in parallel while the walk goes on, not one dependent miss
  // after another in the test. The list's pointers and size are held in
  // locals meanwhile: stores to the list could otherwise be taken to change
  // them (or the cell lists).
  template <int D>
  class Writer {
   public:
    Writer(CandidateList& list, const MotionRecord<D>* records, std::int32_t sentinel, std::int32_t unshifted)
        : list_(list), records_(reinterpret_cast<const double*>(records)), sentinel_(sentinel), unshifted_(unshifted) {
      point();
    }

    // The list starts at `head` and continues at next(k) (negative at the
    // end); its particles are seen through the shift at `shift_offset`.
    template <class Next>
    [[gnu::always_inline]] void append_shifted_list(std::int32_t head, Next next, std::int32_t shift_offset) {
      for (std::int32_t k = head; k >= 0; k = next(static_cast<std::uint32_t>(k))) {
        reserve_one();
        const std::uint32_t offset = record_offset(k);
        __builtin_prefetch(records_ + offset);
        offset_[size_] = offset;
        shift_[size_] = shift_offset;
        ++size_;
      }
    }
    // The same for a prediction that sees no periodic image: its shifts are
    // never read.
    template <class Next>
    [[gnu::always_inline]] void append_list(std::int32_t head, Next next) {
      for (std::int32_t k = head; k >= 0; k = next(static_cast<std::uint32_t>(k))) {
        reserve_one();
        const std::uint32_t offset = record_offset(k);
        __builtin_prefetch(records_ + offset);
        offset_[size_] = offset;
        ++size_;
      }
    }

    std::size_t size() const { return size_; }

    void close() {
      // capacity_ is a multiple of the group, so the last group fits.
      for (std::size_t c = size_; c % group != 0; ++c) {
        offset_[c] = record_offset(sentinel_);
        shift_[c] = unshifted_;
      }
      list_.size_ = size_;
    }

   private:
    static std::uint32_t record_offset(std::int32_t k) {
      return static_cast<std::uint32_t>(k) * static_cast<std::uint32_t>(MotionRecord<D>::stride);
    }

    [[gnu::always_inline]] void reserve_one() {
      if (size_ == capacity_) [[unlikely]] {
        list_.size_ = size_;
        list_.grow();
        point();
      }
    }

    void point() {
      offset_ = list_.offset_.data();
      shift_ = list_.shift_.data();
      capacity_ = list_.capacity_;
    }

    CandidateList& list_;
    const double* records_;  // the motion records as one flat array
    std::int32_t sentinel_;
    std::int32_t unshifted_;
    std::size_t size_ = 0;
    std::size_t capacity_ = 0;
    std::uint32_t* offset_ = nullptr;
    std::int32_t* shift_ = nullptr;
  };

  // Starts the list afresh; `sentinel` is the index of a record no contact
  // test accepts (a NaN position), listed as seen through the zero shift at
  // offset `unshifted`.
  template <int D>
  Writer<D> refill(const MotionRecord<D>* records, std::int32_t sentinel, std::int32_t unshifted) {
    size_ = 0;
    return Writer<D>(*this, records, sentinel, unshifted);
  }

 private:
  [[gnu::noinline]] void grow() {
    // In whole groups, so that close() always has the rest of the last one.
    capacity_ = std::max<std::size_t>(16 * group, 2 * capacity_);
    offset_.resize(capacity_);
    shift_.resize(capacity_);
    times_.resize(capacity_);
  }

  std::vector<std::uint32_t> offset_;
  std::vector<std::int32_t> shift_;
  std::vector<double> times_;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace granflow::edmd
