// Eggers' flux fit against data drawn from the model itself: fluxes
// F(n) = A n^2 exp(-B n^2) per interval, Poisson-distributed, at fractions n
// spread over [0.05, 0.95]; the fit recovers A and B within 5 % (20 000
// intervals: each bin's mean flux has a relative error near 1 %).

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/core/rng.hpp"
#include "systems/dem/compartments.hpp"

namespace granflow::dem {
namespace {

// A Poisson deviate of mean `mean` (small means: multiplying uniforms).
double poisson(Philox& random, double mean) {
  const double limit = std::exp(-mean);
  double product = random.uniform(), k = 0;
  while (product > limit) {
    product *= random.uniform();
    ++k;
  }
  return k;
}

TEST(Compartments, EggersFluxFitRecoversTheModel) {
  for (const double b : {2.0, 6.0}) {
    const double a = 40.0;
    std::vector<double> samples;
    for (int k = 0; k < 20000; ++k) {
      Philox random(21, 22, static_cast<std::uint64_t>(b), static_cast<std::uint64_t>(k));
      const double n = 0.05 + 0.9 * random.uniform();
      samples.push_back(n);
      samples.push_back(poisson(random, a * n * n * std::exp(-b * n * n)));
    }
    const auto fit = fit_eggers_flux(samples);
    std::printf("B = %.1f: fitted A = %.3f, B = %.3f\n", b, fit[0], fit[1]);
    EXPECT_NEAR(fit[0], a, 0.05 * a);
    EXPECT_NEAR(fit[1], b, 0.05 * b);
  }
}

TEST(Compartments, TooFewBinsGiveNoFit) {
  const auto fit = fit_eggers_flux({0.5, 3.0, 0.52, 2.0});
  EXPECT_EQ(fit[0], 0.0);
  EXPECT_EQ(fit[1], 0.0);
}

}  // namespace
}  // namespace granflow::dem
