#pragma once
// What part of the system the World holds while the observers run.
//
// On one process, or where a distributed step gathered every rank's
// particles onto rank 0, the whole: a sum over the World's particles is the
// system's. Where every enabled observer can run on each rank over that
// rank's own particles (System::observes_by_rank; Run::run_observers), the
// World holds one part and the observers meet once per sum: `total` adds
// the ranks' values in rank order, so every rank gets the same bits, and a
// run on a given number of ranks is the same on any thread count. Against
// one rank such sums differ in the last bits only (the same terms, grouped
// by rank).
//
// Cell fields (counts and sums on the unit cells) are held by layer ranges:
// a rank's particles lie in the layers [low, high) of unit cells along
// `axis` (a slab of whole cells), and `whole_field` places every rank's
// layers into the whole grid on rank 0, the one that writes.
//
// Where a rank's particles are a contiguous range of the whole system's
// order (the soft-sphere step keeps them so), `sums` adds their terms in the
// whole's own grouping (ordered_sums.hpp): the same bits as one process.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "engine/core/communicator.hpp"
#include "engine/core/ordered_sums.hpp"

namespace granflow {

class ObservedPart {
 public:
  static constexpr const char* key = "observed_part";
  ObservedPart() = default;
  ObservedPart(const Communicator& ranks, int axis, std::int64_t low, std::int64_t high)
      : ranks_(&ranks), axis_(axis), low_(low), high_(high) {}
  // A part whose particles are the whole order's [first, first + size).
  ObservedPart(const Communicator& ranks, int axis, std::int64_t low, std::int64_t high, std::uint64_t first)
      : ranks_(&ranks), axis_(axis), low_(low), high_(high), first_(first), ordered_(true) {}

  bool whole() const { return ranks_ == nullptr; }
  // Whether this process writes the result file: the one process, or rank 0.
  bool writes() const { return !ranks_ || ranks_->rank() == 0; }

  double total(double mine) const { return whole() ? mine : ranks_->add_across({mine}).front(); }
  std::vector<double> total(const std::vector<double>& mine) const {
    return whole() ? mine : ranks_->add_across(mine);
  }

  // The whole system's binned sums of `term` over this part's `n`
  // particles (ordered_sums), on every rank. Collective.
  template <class Term>
  std::vector<double> sums(std::size_t n, std::size_t bins, std::size_t width, Term&& term) const {
    if (whole()) return ordered_sums(n, bins, width, std::forward<Term>(term));
    if (!ordered_) throw std::logic_error("this part's particles are no range of the whole system's order");
    return sums_from_messages(ranks_->gather_all(part_message(first_, n, width, std::forward<Term>(term))), bins, width);
  }
  // One sum of `term(i)` over the part's n particles, as `sums` adds it.
  template <class Term>
  double sum(std::size_t n, Term&& term) const {
    return sums(n, 1, 1, [&](std::size_t i, double* value) {
      value[0] = term(i);
      return std::size_t{0};
    }).front();
  }

  // The largest of the ranks' values, on every rank.
  double largest(double mine) const {
    if (whole()) return mine;
    const std::vector<double> all = ranks_->gather_all({mine});
    return *std::max_element(all.begin(), all.end());
  }

  // Every rank's `mine`, concatenated in rank order, on the writing rank;
  // nothing on the others.
  std::vector<double> to_writer(const std::vector<double>& mine) const {
    return whole() ? mine : ranks_->gather_to_first(mine);
  }

  // The layers of unit cells this part's particles lie in, along axis():
  // [layer_low(), layer_high()), or `layers`, all of them, for the whole.
  int axis() const { return axis_; }
  std::int64_t layer_low() const { return whole() ? 0 : low_; }
  std::int64_t layer_high(std::int64_t layers) const { return whole() ? layers : high_; }

  // A field of `width` values per unit cell on a grid of `cells` (x fastest),
  // of which each rank holds its layers along axis() (`mine`, in the whole
  // grid's order restricted to them): the whole field on the writing rank,
  // nothing on the others. For the whole, `mine` itself, not copied.
  std::vector<double> whole_field(std::vector<double> mine, const std::vector<std::int32_t>& cells,
                                  std::size_t width) const {
    if (whole()) return mine;
    std::size_t below = width, layers = 1, above = 1;  // values per layer's run, layers, runs
    for (std::size_t a = 0; a < cells.size(); ++a) {
      const auto n = static_cast<std::size_t>(cells[a]);
      if (static_cast<int>(a) < axis_) below *= n;
      else if (static_cast<int>(a) == axis_) layers = n;
      else above *= n;
    }
    const std::vector<double> bounds = to_writer({static_cast<double>(low_), static_cast<double>(high_)});
    const std::vector<double> all = to_writer(mine);
    if (!writes()) return {};
    std::vector<double> field(below * layers * above, 0.0);
    std::size_t from = 0;
    for (std::size_t r = 0; r + 1 < bounds.size(); r += 2) {
      const auto low = static_cast<std::size_t>(bounds[r]), high = static_cast<std::size_t>(bounds[r + 1]);
      const std::size_t run = (high - low) * below;
      if (from + run * above > all.size()) throw std::logic_error("a rank's cell field does not fit its layers");
      for (std::size_t k = 0; k < above; ++k, from += run)
        std::copy(all.begin() + static_cast<std::ptrdiff_t>(from), all.begin() + static_cast<std::ptrdiff_t>(from + run),
                  field.begin() + static_cast<std::ptrdiff_t>((k * layers + low) * below));
    }
    return field;
  }

 private:
  const Communicator* ranks_ = nullptr;
  int axis_ = 0;
  std::int64_t low_ = 0, high_ = 0;
  std::uint64_t first_ = 0;
  bool ordered_ = false;
};

}  // namespace granflow
