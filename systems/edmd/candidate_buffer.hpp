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

  // Appends candidates cell list by cell list with the buffer's pointer and
  // size in locals: stores of candidate data could otherwise be taken to
  // change them (or the cell lists), forcing reloads for every candidate.
  // close() sets the buffer's size and fills the last block with entries no
  // contact test accepts (a NaN position fails the test b < 0).
  class Writer {
   public:
    explicit Writer(CandidateBuffer& buffer) : buffer_(buffer), size_(buffer.size_) { point(); }

    // The list starts at `head` and continues at next(k) (negative at the
    // end); particle k was last advanced at records[k].t and is seen at
    // time `now` through `shift`.
    template <class Next>
    [[gnu::always_inline]] void append_list(std::int32_t head, Next next, const MotionRecord<D>* records,
                                            const Vec<D>& shift, double now) {
      for (std::int32_t k = head; k >= 0; k = next(static_cast<std::uint32_t>(k))) {
        if (size_ == capacity_) [[unlikely]] {
          buffer_.size_ = size_;
          buffer_.grow();
          point();
        }
        const MotionRecord<D>& record = records[k];
        double* entry = data_ + entry_offset(size_++);
        // The same operations in the same order as the reference contact test
        // (x + v (now - t), then the shift), so predicted times stay bit-identical.
        const double age = now - record.t;
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

    std::size_t size() const { return size_; }

    void close() {
      for (std::size_t c = size_; c % block != 0; ++c) data_[entry_offset(c)] = std::numeric_limits<double>::quiet_NaN();
      buffer_.size_ = size_;
    }

   private:
    void point() {
      data_ = buffer_.storage_.data();
      capacity_ = buffer_.capacity_;
    }

    CandidateBuffer& buffer_;
    std::size_t size_;
    std::size_t capacity_ = 0;
    double* data_ = nullptr;
  };

  // Starts filling the buffer afresh.
  Writer refill() {
    size_ = 0;
    return Writer(*this);
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
  }

  std::vector<double> storage_;
  std::vector<double> times_;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace granflow::edmd
