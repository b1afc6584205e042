// The mixed-radix transform of a line against the plain sum over its
// values, for every length up to 64 (primes, powers of two, mixed) and the
// grid edges of the SRD studies, read with a stride as the field's axes are.

#include "systems/srd/fourier_line.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <vector>

namespace granflow::srd {
namespace {

// sum_j x_j exp(-2 pi i j m / L), each term's phase reduced to j m mod L.
std::vector<std::complex<double>> plain_sum(const std::vector<std::complex<double>>& x) {
  const std::size_t n = x.size();
  std::vector<std::complex<double>> out(n);
  for (std::size_t m = 0; m < n; ++m)
    for (std::size_t j = 0; j < n; ++j)
      out[m] += x[j] * std::polar(1.0, -2.0 * std::numbers::pi * static_cast<double>(j * m % n) /
                                           static_cast<double>(n));
  return out;
}

// Cell counts as the clustering transforms them, and a complex line: a
// fixed pseudo-random sequence.
std::vector<std::complex<double>> values(std::size_t n, bool real) {
  std::vector<std::complex<double>> out(n);
  std::uint64_t state = 12345 + n;
  const auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 40) / static_cast<double>(1ull << 24);
  };
  for (auto& v : out) {
    const double a = next(), b = next();
    v = real ? std::complex<double>(std::floor(20.0 * a), 0.0) : std::complex<double>(a, b - 0.5);
  }
  return out;
}

void expect_transform(std::size_t n, bool real) {
  const auto x = values(n, real);
  const auto expected = plain_sum(x);
  // Every third value of a longer array: the stride the field's axes have.
  std::vector<std::complex<double>> strided(3 * n);
  for (std::size_t j = 0; j < n; ++j) strided[3 * j] = x[j];
  std::vector<std::complex<double>> out(n);
  FourierLine(n).transform(strided.data(), 3, out.data());
  double scale = 0.0;
  for (const auto& v : expected) scale = std::max(scale, std::abs(v));
  for (std::size_t m = 0; m < n; ++m)
    ASSERT_LE(std::abs(out[m] - expected[m]), 1e-13 * std::max(scale, 1.0)) << "L = " << n << ", m = " << m;
}

TEST(FourierLine, EveryLengthUpTo64MatchesThePlainSum) {
  for (std::size_t n = 1; n <= 64; ++n) {
    expect_transform(n, true);
    expect_transform(n, false);
  }
}

TEST(FourierLine, TheStudiesGridEdgesMatchThePlainSum) {
  for (std::size_t n : {80u, 97u, 120u, 128u, 200u, 210u, 256u}) expect_transform(n, true);
}

// Parseval: sum |X_m|^2 = L sum |x_j|^2, which the structure factor's
// normalisation rests on.
TEST(FourierLine, ThePowerIsLTimesTheSumOfSquares) {
  for (std::size_t n : {200u, 243u, 1024u}) {
    const auto x = values(n, true);
    std::vector<std::complex<double>> out(n);
    FourierLine(n).transform(x.data(), 1, out.data());
    double in_power = 0.0, out_power = 0.0;
    for (const auto& v : x) in_power += std::norm(v);
    for (const auto& v : out) out_power += std::norm(v);
    EXPECT_NEAR(out_power, static_cast<double>(n) * in_power, 1e-12 * out_power) << "L = " << n;
  }
}

}  // namespace
}  // namespace granflow::srd
