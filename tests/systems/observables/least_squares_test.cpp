// The fits against exact data (recovered to round-off) and against a
// slower reference: the normal equations solved by Cramer's rule in long
// double for noisy data.

#include "systems/observables/least_squares.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace granflow {
namespace {

TEST(LineFit, RecoversAnExactLineAndWeightsPoints) {
  LineFit fit;
  for (int k = 0; k < 10; ++k) fit.add(0.3 * k, 1.5 - 2.0 * 0.3 * k);
  EXPECT_NEAR(fit.slope(), -2.0, 1e-13);
  EXPECT_NEAR(fit.intercept(), 1.5, 1e-13);
  // A weight w counts as w copies of the point.
  LineFit weighted, repeated;
  const double x[3] = {0.0, 1.0, 3.0}, y[3] = {1.0, 2.5, 3.0};
  for (int k = 0; k < 3; ++k) {
    weighted.add(x[k], y[k], k + 1.0);
    for (int copy = 0; copy <= k; ++copy) repeated.add(x[k], y[k]);
  }
  EXPECT_NEAR(weighted.slope(), repeated.slope(), 1e-14);
  EXPECT_NEAR(weighted.intercept(), repeated.intercept(), 1e-14);
}

TEST(LineFit, HasNoSlopeWithoutTwoDistinctAbscissae) {
  LineFit fit;
  EXPECT_TRUE(std::isnan(fit.slope()));
  fit.add(2.0, 1.0);
  fit.add(2.0, 3.0);
  EXPECT_EQ(fit.points(), 2u);
  EXPECT_TRUE(std::isnan(fit.slope()));
}

// The slope's standard error against its textbook form
// s / sqrt(sum (x - mean x)^2), s^2 the residual variance over n - 2, and
// against the scatter of slopes fitted to many noisy lines (within 5 %).
TEST(LineFit, SlopeStandardErrorIsTheScatterOfFittedSlopes) {
  std::mt19937_64 engine(7);
  std::normal_distribution<double> noise(0.0, 0.4);
  std::vector<double> x;
  for (int k = 0; k < 20; ++k) x.push_back(0.5 * k);
  double mean_x = 0.0;
  for (double v : x) mean_x += v / x.size();
  double sxx = 0.0;
  for (double v : x) sxx += (v - mean_x) * (v - mean_x);
  double sum = 0.0, squares = 0.0, errors = 0.0;
  const int fits = 4000;
  for (int f = 0; f < fits; ++f) {
    LineFit fit;
    std::vector<double> y;
    for (double v : x) y.push_back(1.0 + 0.7 * v + noise(engine));
    for (std::size_t k = 0; k < x.size(); ++k) fit.add(x[k], y[k]);
    if (f == 0) {
      double residual = 0.0;
      for (std::size_t k = 0; k < x.size(); ++k) {
        const double r = y[k] - fit.intercept() - fit.slope() * x[k];
        residual += r * r;
      }
      EXPECT_NEAR(fit.slope_standard_error(), std::sqrt(residual / (x.size() - 2.0) / sxx), 1e-12);
    }
    sum += fit.slope();
    squares += fit.slope() * fit.slope();
    errors += fit.slope_standard_error() / fits;
  }
  const double scatter = std::sqrt(squares / fits - (sum / fits) * (sum / fits));
  EXPECT_NEAR(errors / scatter, 1.0, 0.05);
  LineFit two;
  two.add(0.0, 1.0);
  two.add(1.0, 2.0);
  EXPECT_TRUE(std::isnan(two.slope_standard_error()));
}

TEST(OffsetPowerLaw, RecoversExponentAmplitudeAndOffset) {
  std::vector<double> x, y;
  for (int k = 0; k < 40; ++k) {
    x.push_back(std::pow(10.0, 0.1 * k));
    y.push_back(-6.0 + 5.5 * std::pow(x.back(), 1.0 / 6.0));
  }
  const auto fit = fit_offset_power_law(x, y, 0.01, 2.0);
  EXPECT_NEAR(fit.exponent, 1.0 / 6.0, 1e-7);
  EXPECT_NEAR(fit.amplitude, 5.5, 1e-5);
  EXPECT_NEAR(fit.offset, -6.0, 1e-5);
}

TEST(FitParabola, RecoversAnExactParabola) {
  std::vector<double> x, y;
  for (int k = 0; k < 20; ++k) {
    x.push_back(k + 0.5);
    y.push_back(0.2 + 0.7 * x.back() - 0.01 * x.back() * x.back());
  }
  const auto c = fit_parabola(x, y);
  EXPECT_NEAR(c[0], 0.2, 1e-11);
  EXPECT_NEAR(c[1], 0.7, 1e-12);
  EXPECT_NEAR(c[2], -0.01, 1e-13);
}

TEST(FitParabola, AgreesWithCramersRuleOnNoisyData) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> x, y;
  for (int k = 0; k < 50; ++k) {
    x.push_back(-1.0 + 0.04 * k);
    y.push_back(1.0 - 3.0 * x.back() * x.back() + noise(random));
  }
  long double s[5] = {}, t[3] = {};
  for (std::size_t k = 0; k < x.size(); ++k) {
    long double p = 1;
    for (int m = 0; m < 5; ++m, p *= x[k]) s[m] += p;
    p = 1;
    for (int m = 0; m < 3; ++m, p *= x[k]) t[m] += p * y[k];
  }
  const auto det3 = [](long double a, long double b, long double c, long double d, long double e, long double f,
                       long double g, long double h, long double i) {
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  };
  const long double d = det3(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);
  const long double c0 = det3(t[0], s[1], s[2], t[1], s[2], s[3], t[2], s[3], s[4]) / d;
  const long double c1 = det3(s[0], t[0], s[2], s[1], t[1], s[3], s[2], t[2], s[4]) / d;
  const long double c2 = det3(s[0], s[1], t[0], s[1], s[2], t[1], s[2], s[3], t[2]) / d;
  const auto c = fit_parabola(x, y);
  EXPECT_NEAR(c[0], static_cast<double>(c0), 1e-12);
  EXPECT_NEAR(c[1], static_cast<double>(c1), 1e-12);
  EXPECT_NEAR(c[2], static_cast<double>(c2), 1e-12);
  EXPECT_NEAR(c[2], -3.0, 0.2);  // and the noise leaves the curvature near the truth
}

}  // namespace
}  // namespace granflow
