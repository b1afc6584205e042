#pragma once
// A Communicator for unit tests of collective code, as rank 0 of two sees
// it: what rank 1 contributes to each collective call, in call order.

#include <deque>
#include <stdexcept>
#include <vector>

#include "engine/core/communicator.hpp"

namespace granflow {

class FirstOfTwo final : public Communicator {
 public:
  mutable std::deque<std::vector<double>> from_second;
  int rank() const override { return 0; }
  int size() const override { return 2; }
  Received exchange_with_neighbours(int, const std::vector<double>&, int, const std::vector<double>&,
                                    int) const override {
    return {};
  }
  std::vector<double> gather_all(const std::vector<double>& mine) const override {
    std::vector<double> all = mine;
    const std::vector<double> theirs = next();
    all.insert(all.end(), theirs.begin(), theirs.end());
    return all;
  }
  std::int64_t sum(std::int64_t value) const override {
    const std::vector<double> theirs = next();
    return value + (theirs.empty() ? 0 : static_cast<std::int64_t>(theirs.front()));
  }
  bool from_first(bool value) const override { return value; }

 private:
  std::vector<double> next() const {
    if (from_second.empty()) throw std::logic_error("a collective call rank 1 was not given a part in");
    std::vector<double> front = std::move(from_second.front());
    from_second.pop_front();
    return front;
  }
};

}  // namespace granflow
