#pragma once
// Least-squares fits of the analyses: a weighted straight line and a
// parabola. The line keeps its five running sums so that a caller can fit
// points as it visits them, without storing them.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace granflow {

// y = intercept + slope x by weighted least squares.
class LineFit {
 public:
  void add(double x, double y, double weight = 1.0) {
    sw_ += weight;
    sx_ += weight * x;
    sy_ += weight * y;
    sxx_ += weight * x * x;
    sxy_ += weight * x * y;
    syy_ += weight * y * y;
    ++points_;
  }
  std::size_t points() const { return points_; }
  // sum w * sum w x^2 - (sum w x)^2: positive when two distinct abscissae have weight.
  double determinant() const { return sw_ * sxx_ - sx_ * sx_; }
  // nan with fewer than two distinct abscissae.
  double slope() const {
    const double det = determinant();
    return det > 0 ? (sw_ * sxy_ - sx_ * sy_) / det : std::nan("");
  }
  double intercept() const { return (sy_ - slope() * sx_) / sw_; }
  // The slope's standard error from the scatter about the line, for unit
  // weights (nan with fewer than three points). Where the points are not
  // independent (a smooth series) it measures the fit, not a statistical error.
  double slope_standard_error() const {
    if (points_ < 3 || !(determinant() > 0)) return std::nan("");
    const double residual = std::max(0.0, syy_ - intercept() * sy_ - slope() * sxy_) / (static_cast<double>(points_) - 2.0);
    return std::sqrt(residual * sw_ / determinant());
  }

 private:
  double sw_ = 0, sx_ = 0, sy_ = 0, sxx_ = 0, sxy_ = 0, syy_ = 0;
  std::size_t points_ = 0;
};

// Coefficients {c0, c1, c2} of y = c0 + c1 x + c2 x^2 through `count`
// points, by the normal equations solved with Gauss-Jordan elimination
// (their matrix is positive definite when three abscissae differ, so no
// pivoting is needed). `x_of(k)`, `y_of(k)`: the k-th point.
template <class X, class Y>
std::array<double, 3> fit_parabola(std::size_t count, X x_of, Y y_of) {
  double m[3][4] = {};
  for (std::size_t k = 0; k < count; ++k) {
    const double x = x_of(k), y = y_of(k), p[3] = {1.0, x, x * x};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] += p[r] * p[c];
      m[r][3] += p[r] * y;
    }
  }
  for (int col = 0; col < 3; ++col)
    for (int r = 0; r < 3; ++r) {
      if (r == col) continue;
      const double f = m[r][col] / m[col][col];
      for (int c = col; c < 4; ++c) m[r][c] -= f * m[col][c];
    }
  return {m[0][3] / m[0][0], m[1][3] / m[1][1], m[2][3] / m[2][2]};
}

inline std::array<double, 3> fit_parabola(const std::vector<double>& x, const std::vector<double>& y) {
  return fit_parabola(
      x.size(), [&](std::size_t k) { return x[k]; }, [&](std::size_t k) { return y[k]; });
}

// y = offset + amplitude x^exponent by least squares: for each exponent the
// offset and amplitude are linear, and the exponent minimising the residual
// is found by golden-section search in [low, high] (the residual must have
// one minimum there). A growth law whose early part differs, such as an
// MSD that approaches c + a t^gamma, has the exponent of its late part.
struct OffsetPowerLaw {
  double exponent = std::nan(""), amplitude = std::nan(""), offset = std::nan("");
};
inline OffsetPowerLaw fit_offset_power_law(const std::vector<double>& x, const std::vector<double>& y, double low,
                                           double high) {
  const auto solve = [&](double exponent, OffsetPowerLaw* out) {
    LineFit fit;
    for (std::size_t k = 0; k < x.size(); ++k) fit.add(std::pow(x[k], exponent), y[k]);
    const double a = fit.slope(), c = fit.intercept();
    double residual = 0.0;
    for (std::size_t k = 0; k < x.size(); ++k) {
      const double r = y[k] - c - a * std::pow(x[k], exponent);
      residual += r * r;
    }
    if (out) *out = {exponent, a, c};
    return residual;
  };
  OffsetPowerLaw out;
  if (x.size() < 3) return out;
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = low, b = high;
  double c = b - ratio * (b - a), d = a + ratio * (b - a);
  double fc = solve(c, nullptr), fd = solve(d, nullptr);
  for (int k = 0; k < 100 && b - a > 1e-10; ++k) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - ratio * (b - a);
      fc = solve(c, nullptr);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + ratio * (b - a);
      fd = solve(d, nullptr);
    }
  }
  solve(0.5 * (a + b), &out);
  return out;
}

}  // namespace granflow
