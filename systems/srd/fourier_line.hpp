#pragma once
// The discrete Fourier transform of a line of L complex values,
//   X_m = sum_j x_j exp(-2 pi i j m / L),
// by mixed-radix decimation in time: L is split into its prime factors,
// and each stage combines the sub-transforms with the factor's own small
// transform. The cost is L times the sum of the factors (L log L for the
// smooth lengths grids have, 200 = 2^3 5^2: 16 L against L^2 = 200 L for
// the plain sum); a prime length costs what the plain sum does. Every
// twiddle comes from one table of exp(-2 pi i k / L), so the arithmetic,
// and with it the round-off, is fixed by L alone: the same on every line,
// thread and rank.

#include <complex>
#include <cstddef>
#include <numbers>
#include <vector>

namespace granflow::srd {

class FourierLine {
 public:
  explicit FourierLine(std::size_t length) : length_(length), table_(length) {
    for (std::size_t k = 0; k < length; ++k)
      table_[k] = std::polar(1.0, -2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(length));
    for (std::size_t rest = length, p = 2; rest > 1;) {
      if (p * p > rest) p = rest;  // what is left is prime
      if (rest % p == 0) {
        factors_.push_back(p);
        rest /= p;
      } else {
        ++p;
      }
    }
  }

  std::size_t length() const { return length_; }

  // out[m] = X_m of in[0], in[stride], ..., in[(L - 1) stride]; `out` holds
  // L values and must not overlap `in`.
  void transform(const std::complex<double>* in, std::size_t stride, std::complex<double>* out) const {
    if (length_ == 1) {
      out[0] = in[0];
      return;
    }
    stage(in, stride, out, length_, 0);
  }

 private:
  // The transform of the n values in[0], in[stride], ... into out[0 .. n),
  // n = the product of factors_[f ..]: the transforms of its p = factors_[f]
  // interleaved sub-lines, each of n / p values, into out's p blocks, then
  // combined in place, X_{k + q m} = sum_r W_p^{r q} (W_n^{r k} Y_r[k]).
  void stage(const std::complex<double>* in, std::size_t stride, std::complex<double>* out, std::size_t n,
             std::size_t f) const {
    const std::size_t p = factors_[f], m = n / p;
    const std::size_t step_n = length_ / n, step_p = length_ / p;  // W_n^k = table_[k step_n]
    if (m == 1) {
      for (std::size_t q = 0; q < p; ++q) {
        std::complex<double> sum = in[0];
        for (std::size_t r = 1; r < p; ++r) sum += in[r * stride] * table_[(r * q % p) * step_p];
        out[q] = sum;
      }
      return;
    }
    for (std::size_t r = 0; r < p; ++r) stage(in + r * stride, stride * p, out + r * m, m, f + 1);
    std::complex<double> turned[max_direct];
    std::vector<std::complex<double>> turned_long(p > max_direct ? p : 0);
    std::complex<double>* t = p > max_direct ? turned_long.data() : turned;
    for (std::size_t k = 0; k < m; ++k) {
      t[0] = out[k];
      for (std::size_t r = 1; r < p; ++r) t[r] = out[r * m + k] * table_[r * k * step_n];
      for (std::size_t q = 0; q < p; ++q) {
        std::complex<double> sum = t[0];
        for (std::size_t r = 1; r < p; ++r) sum += t[r] * table_[(r * q % p) * step_p];
        out[q * m + k] = sum;
      }
    }
  }

  static constexpr std::size_t max_direct = 64;  // factors up to this combine in a buffer on the stack
  std::size_t length_;
  std::vector<std::complex<double>> table_;
  std::vector<std::size_t> factors_;
};

}  // namespace granflow::srd
