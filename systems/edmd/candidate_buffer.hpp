#pragma once
// The candidate partners of one prediction, copied out of the cell lists into
// scratch with their positions already moved to the time of the prediction
// and shifted to the periodic image in view. The layout is blocks of `block`
// candidates, each block holding every field of its candidates as one row of
// `block` doubles: the contact test reads each field with contiguous vector
// loads instead of gathers, and filling the buffer needs a single pointer.
// A candidate in a cell that both particles of a collision see is copied once
// and tested by both (each tests its own range of the buffer).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "components/vector.hpp"
#include "systems/edmd/motion_record.hpp"

namespace granflow::edmd {

template <int D>
class CandidateBuffer {
 public:
  // The contact test runs over whole blocks, so that it needs no scalar
  // remainder loop: testing a particle of the buffer outside a range does no
  // harm (it is a real particle, in cells too far away to be reached before a
  // cell crossing), and Writer::close() fills the rest of the last block with
  // entries no test accepts.
  static constexpr std::size_t block = 8;
  // Rows of a block: position, velocity, radius, and the particle's index
  // (exact as a double).
  static constexpr std::size_t radius_row = 2 * D;
  static constexpr std::size_t index_row = 2 * D + 1;
  static constexpr std::size_t rows = 2 * D + 2;

  CandidateBuffer() { grow(); }

  std::size_t size() const { return size_; }

  // Appends candidates cell list by cell list, in two passes: the lists are
  // walked first, noting each candidate's index and prefetching its record,
  // so that the records of all candidates are fetched from memory in
  // parallel rather than one dependent miss after another; close() then
  // copies them and fills the rest of the last block with entries no contact
  // test accepts (a NaN position fails the test b < 0). The buffer's pointers
  // and size are held in locals meanwhile: stores of candidate data could
  // otherwise be taken to change them (or the cell lists).
  class Writer {
   public:
    // Particle k was last advanced at records[k].t; all are seen at time `now`.
    Writer(CandidateBuffer& buffer, const MotionRecord<D>* records, double now)
        : buffer_(buffer), records_(records), now_(now), size_(buffer.size_), copied_(buffer.size_) {
      point();
    }

    // The list starts at `head` and continues at next(k) (negative at the
    // end); its particles are seen through `shift`.
    template <class Next>
    [[gnu::always_inline]] void append_list(std::int32_t head, Next next, const Vec<D>& shift) {
      if (head < 0) return;
      if (segments_ == max_segments) [[unlikely]] copy();
      for (std::int32_t k = head; k >= 0; k = next(static_cast<std::uint32_t>(k))) {
        if (size_ == capacity_) [[unlikely]] {
          buffer_.size_ = size_;
          buffer_.grow();
          point();
        }
        __builtin_prefetch(&records_[k]);
        pending_[size_++] = static_cast<std::uint32_t>(k);
      }
      segment_[segments_++] = {size_, &shift};
    }

    std::size_t size() const { return size_; }

    void close() {
      copy();
      for (std::size_t c = size_; c % block != 0; ++c) data_[entry_offset(c)] = std::numeric_limits<double>::quiet_NaN();
      buffer_.size_ = size_;
    }

   private:
    static constexpr int max_segments = 64;

    void copy() {
      std::size_t c = copied_;
      for (int s = 0; s < segments_; ++s) {
        const Vec<D>& shift = *segment_[s].shift;
        for (; c < segment_[s].end; ++c) {
          const std::uint32_t k = pending_[c];
          const MotionRecord<D>& record = records_[k];
          double* entry = data_ + entry_offset(c);
          // The same operations in the same order as the reference contact
          // test (x + v (now - t), then the shift), so predicted times stay
          // bit-identical.
          const double age = now_ - record.t;
          for (int a = 0; a < D; ++a) {
            const double v = record.v[a];
            double x = record.x[a] + v * age;
            x += shift[a];
            entry[static_cast<std::size_t>(a) * block] = x;
            entry[static_cast<std::size_t>(D + a) * block] = v;
          }
          entry[radius_row * block] = record.r;
          entry[index_row * block] = static_cast<double>(k);
        }
      }
      copied_ = c;
      segments_ = 0;
    }

    void point() {
      data_ = buffer_.storage_.data();
      pending_ = buffer_.pending_.data();
      capacity_ = buffer_.capacity_;
    }

    struct Segment {
      std::size_t end;
      const Vec<D>* shift;
    };
    CandidateBuffer& buffer_;
    const MotionRecord<D>* records_;
    double now_;
    std::size_t size_;
    std::size_t copied_;
    std::size_t capacity_ = 0;
    double* data_ = nullptr;
    std::uint32_t* pending_ = nullptr;
    Segment segment_[max_segments];
    int segments_ = 0;
  };

  // Starts filling the buffer afresh.
  Writer refill(const MotionRecord<D>* records, double now) {
    size_ = 0;
    return Writer(*this, records, now);
  }

  // Where entry c's first row lies; row f is f * block further.
  static std::size_t entry_offset(std::size_t c) { return (c / block) * rows * block + c % block; }
  const double* data() const { return storage_.data(); }
  std::uint32_t index(std::size_t c) const { return static_cast<std::uint32_t>(storage_[entry_offset(c) + index_row * block]); }
  // Room for one contact time per entry, the last block whole.
  double* times() { return times_.data(); }

 private:
  [[gnu::noinline]] void grow() {
    // In whole blocks, so that close() always has the rest of the last one.
    capacity_ = std::max<std::size_t>(8 * block, 2 * capacity_);
    storage_.resize(rows * capacity_, 0.0);
    times_.resize(capacity_);
    pending_.resize(capacity_);
  }

  std::vector<double> storage_;
  std::vector<double> times_;
  std::vector<std::uint32_t> pending_;  // candidates noted but not copied yet
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace granflow::edmd
