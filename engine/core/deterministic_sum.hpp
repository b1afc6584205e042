#pragma once
// Parallel sum over n terms with a fixed summation order: fixed-size chunks
// summed in parallel, then the chunk sums in order, so the result is the same
// bit for bit on any number of threads.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace granflow {

template <class Term>
double deterministic_sum(std::size_t n, Term&& term) {
  constexpr std::size_t chunk = 4096;
  const std::size_t chunks = (n + chunk - 1) / chunk;
  std::vector<double> partial(chunks, 0.0);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    double sum = 0.0;
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) sum += term(i);
    partial[c] = sum;
  });
  double total = 0.0;
  for (double p : partial) total += p;
  return total;
}

}  // namespace granflow
