#pragma once
// Binned sums over particles taken in one fixed grouping, so that a system
// split over ranks gets the bits one process gets.
//
// The particles have a whole order (index 0 .. n-1 of the whole system) and
// the grouping is fixed by it alone: chunks of `ordered_chunk` consecutive
// indices, each bin summed within a chunk from its first term on, then the
// chunks' sums of each bin added in chunk order. One process computes the
// chunks in parallel (any thread count gives the same bits). A rank that
// holds the contiguous indices [first, first + count) sums the chunks that
// lie wholly inside its range and passes the terms of the chunks it shares
// with its neighbours on as they are (part_message); the ranks' messages, in
// rank order, give the whole's sums (sums_from_messages). A chunk shared by
// several ranks is summed from their terms in the whole order, as one
// process sums it. With one bin this is deterministic_sum's grouping.
//
// A term is a bin (or no_bin, where the particle adds to none) and `width`
// values added to that bin.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

namespace granflow {

inline constexpr std::size_t ordered_chunk = 4096;
inline constexpr std::size_t no_bin = std::numeric_limits<std::size_t>::max();

namespace ordered_sums_detail {

// One chunk's sums: the bins it touched (each bin's total is apart, so
// their order does not matter) and their sums, each from its first term on.
struct ChunkSums {
  std::vector<std::size_t> bins;
  std::vector<double> sums;  // width per bin
  std::unordered_map<std::size_t, std::size_t> at;  // a bin's place in `bins`

  void add(std::size_t bin, const double* values, std::size_t width) {
    const auto [it, added] = at.try_emplace(bin, bins.size());
    if (added) {
      bins.push_back(bin);
      sums.resize(sums.size() + width, 0.0);
    }
    double* s = sums.data() + it->second * width;
    for (std::size_t k = 0; k < width; ++k) s[k] += values[k];
  }
};

// The chunk of the terms [from, to) of `term` (indices of the caller's own).
template <class Term>
ChunkSums chunk_sums(std::size_t from, std::size_t to, std::size_t width, Term& term, std::vector<double>& values) {
  ChunkSums chunk;
  for (std::size_t i = from; i < to; ++i)
    if (const std::size_t bin = term(i, values.data()); bin != no_bin) chunk.add(bin, values.data(), width);
  return chunk;
}

inline void add_chunk(const ChunkSums& chunk, std::size_t width, std::vector<double>& total) {
  for (std::size_t b = 0; b < chunk.bins.size(); ++b)
    for (std::size_t k = 0; k < width; ++k) total[chunk.bins[b] * width + k] += chunk.sums[b * width + k];
}

inline void check_bin(std::size_t bin, std::size_t bins) {
  if (bin != no_bin && bin >= bins) throw std::out_of_range("ordered_sums: a term's bin lies outside the bins");
}

// The whole chunks of a part starting at whole index `first` with `count`
// terms: [head_end, tail_begin) in the part's own indices.
struct PartLayout {
  std::size_t head_end = 0, tail_begin = 0;
  PartLayout(std::uint64_t first, std::size_t count) {
    const std::size_t into = static_cast<std::size_t>(first % ordered_chunk);
    head_end = std::min(count, into == 0 ? 0 : ordered_chunk - into);
    const std::size_t whole_chunks = (count - head_end) / ordered_chunk;
    tail_begin = head_end + whole_chunks * ordered_chunk;
  }
};

}  // namespace ordered_sums_detail

// The sums of the whole system's `n` terms, bins x width values.
// `term(i, values)` fills `values` (width of them) and returns i's bin.
template <class Term>
std::vector<double> ordered_sums(std::size_t n, std::size_t bins, std::size_t width, Term&& term) {
  using namespace ordered_sums_detail;
  const std::size_t chunks = (n + ordered_chunk - 1) / ordered_chunk;
  std::vector<ChunkSums> parts(chunks);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::vector<double> values(width);
    parts[c] = chunk_sums(c * ordered_chunk, std::min(n, (c + 1) * ordered_chunk), width, term, values);
  });
  std::vector<double> total(bins * width, 0.0);
  for (const ChunkSums& chunk : parts) {
    for (const std::size_t bin : chunk.bins) check_bin(bin, bins);
    add_chunk(chunk, width, total);
  }
  return total;
}

// A rank's share of ordered_sums: its `count` terms are the whole's
// [first, first + count). The message holds first and count, the terms of
// the chunk it shares with the rank below (bin, then the values; -1 for
// none), the sums of its whole chunks (per chunk: the bins touched, then
// each bin and its values), and the terms of the chunk it shares above.
template <class Term>
std::vector<double> part_message(std::uint64_t first, std::size_t count, std::size_t width, Term&& term) {
  using namespace ordered_sums_detail;
  const PartLayout layout(first, count);
  std::vector<double> values(width);
  std::vector<double> out{static_cast<double>(first), static_cast<double>(count)};
  const auto add_terms = [&](std::size_t from, std::size_t to) {
    for (std::size_t i = from; i < to; ++i) {
      const std::size_t bin = term(i, values.data());
      out.push_back(bin == no_bin ? -1.0 : static_cast<double>(bin));
      out.insert(out.end(), values.begin(), values.end());
    }
  };
  add_terms(0, layout.head_end);
  const std::size_t chunks = (layout.tail_begin - layout.head_end) / ordered_chunk;
  std::vector<ChunkSums> parts(chunks);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::vector<double> scratch(width);
    const std::size_t from = layout.head_end + c * ordered_chunk;
    parts[c] = chunk_sums(from, from + ordered_chunk, width, term, scratch);
  });
  for (const ChunkSums& chunk : parts) {
    out.push_back(static_cast<double>(chunk.bins.size()));
    for (std::size_t b = 0; b < chunk.bins.size(); ++b) {
      out.push_back(static_cast<double>(chunk.bins[b]));
      out.insert(out.end(), chunk.sums.begin() + static_cast<std::ptrdiff_t>(b * width),
                 chunk.sums.begin() + static_cast<std::ptrdiff_t>((b + 1) * width));
    }
  }
  add_terms(layout.tail_begin, count);
  return out;
}

// The whole's sums from every rank's part_message, concatenated in rank
// order (the ranks' ranges following each other from index 0).
inline std::vector<double> sums_from_messages(const std::vector<double>& all, std::size_t bins, std::size_t width) {
  using namespace ordered_sums_detail;
  std::vector<double> total(bins * width, 0.0);
  // The chunk being summed from terms, as one process sums it.
  std::size_t open = no_bin;
  ChunkSums open_sums;
  const auto close = [&] {
    if (open == no_bin) return;
    add_chunk(open_sums, width, total);
    open = no_bin;
    open_sums = {};
  };
  std::size_t at = 0;
  const auto need = [&](std::size_t values) {
    if (at + values > all.size()) throw std::runtime_error("ordered_sums: a rank's message ends early");
  };
  std::uint64_t expected_first = 0;
  while (at < all.size()) {
    need(2);
    const auto first = static_cast<std::uint64_t>(all[at]);
    const auto count = static_cast<std::size_t>(all[at + 1]);
    at += 2;
    if (first != expected_first) throw std::runtime_error("ordered_sums: the ranks' ranges do not follow each other");
    expected_first = first + count;
    const PartLayout layout(first, count);
    const auto take_terms = [&](std::size_t from, std::size_t to) {
      for (std::size_t i = from; i < to; ++i) {
        need(1 + width);
        const std::size_t chunk = static_cast<std::size_t>((first + i) / ordered_chunk);
        if (chunk != open) {
          close();
          open = chunk;
        }
        const double bin_value = all[at++];
        if (bin_value >= 0.0) {
          const auto bin = static_cast<std::size_t>(bin_value);
          check_bin(bin, bins);
          open_sums.add(bin, all.data() + at, width);
        }
        at += width;
      }
    };
    take_terms(0, layout.head_end);
    for (std::size_t c = 0; c < (layout.tail_begin - layout.head_end) / ordered_chunk; ++c) {
      close();
      need(1);
      const auto touched = static_cast<std::size_t>(all[at++]);
      ChunkSums chunk;
      for (std::size_t b = 0; b < touched; ++b) {
        need(1 + width);
        chunk.bins.push_back(static_cast<std::size_t>(all[at]));
        check_bin(chunk.bins.back(), bins);
        chunk.sums.insert(chunk.sums.end(), all.begin() + static_cast<std::ptrdiff_t>(at + 1),
                          all.begin() + static_cast<std::ptrdiff_t>(at + 1 + width));
        at += 1 + width;
      }
      add_chunk(chunk, width, total);
    }
    take_terms(layout.tail_begin, count);
  }
  close();
  return total;
}

}  // namespace granflow
