// The vectorised pair kernel against the contact law evaluated pair by pair
// (contact_law.hpp, scalar): every pair's force and the totals of elastic
// energy, dissipation and contacts, for the spring-dashpot and Hertz, equal
// and unequal spheres, across a periodic boundary, and for ranges that start and
// end anywhere (the vector loop's remainders). Tolerance 1e-12 relative:
// only the order of the sums differs.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "engine/core/rng.hpp"
#include "systems/dem/contact_law.hpp"
#include "systems/dem/pair_kernel.hpp"

namespace granflow::dem {
namespace {

struct Pairs {
  static constexpr double side = 6.0;
  std::vector<double> x, v, radius, mass;
  std::vector<std::uint32_t> first, second;

  Pairs(std::size_t n, bool polydisperse) {
    for (std::size_t i = 0; i < n; ++i) {
      Philox random(7, 8, 9, i);
      for (int a = 0; a < 3; ++a) x.push_back(side * random.uniform());
      for (int a = 0; a < 3; ++a) v.push_back(random.normal());
      radius.push_back(polydisperse ? 0.4 + 0.2 * random.uniform() : 0.5);
      mass.push_back(polydisperse ? 0.5 + random.uniform() : 1.0);
    }
    // Every pair within 1.3 (the lists' reach with a skin): about half in contact.
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t j = i + 1; j < n; ++j) {
        double d2 = 0.0;
        for (int a = 0; a < 3; ++a) {
          const double d = separation(i, j, a);
          d2 += d * d;
        }
        if (d2 < 1.3 * 1.3) {
          first.push_back(i);
          second.push_back(j);
        }
      }
  }
  // Periodic along x only.
  double separation(std::size_t i, std::size_t j, int a) const {
    double d = x[3 * i + a] - x[3 * j + a];
    if (a == 0) d -= side * std::round(d / side);
    return d;
  }
};

// polydisperse: radii and masses differ (else the kernel's one-radius,
// one-mass path).
void expect_kernel_matches_law(const ContactLaw& law, bool polydisperse) {
  const Pairs pairs(300, polydisperse);
  ASSERT_GT(pairs.first.size(), 200u);
  PairSweep<3> sweep;
  sweep.x = pairs.x.data();
  sweep.v = pairs.v.data();
  sweep.radius = pairs.radius.data();
  sweep.mass = pairs.mass.data();
  sweep.first = pairs.first.data();
  sweep.second = pairs.second.data();
  sweep.length[0] = sweep.length[1] = sweep.length[2] = Pairs::side;
  sweep.half[0] = 0.5 * Pairs::side;
  sweep.half[1] = sweep.half[2] = INFINITY;
  sweep.law = law;
  sweep.uniform_mass = !polydisperse;
  sweep.same_radius = !polydisperse;
  const std::size_t count = pairs.first.size();
  // The reference, pair by pair.
  std::vector<double> expected(3 * count, 0.0);
  double elastic = 0.0, dissipated = 0.0, contacts = 0.0;
  for (std::size_t p = 0; p < count; ++p) {
    const std::size_t i = pairs.first[p], j = pairs.second[p];
    double d[3], d2 = 0.0, closing = 0.0;
    for (int a = 0; a < 3; ++a) {
      d[a] = pairs.separation(i, j, a);
      d2 += d[a] * d[a];
    }
    const double distance = std::sqrt(d2), reach = pairs.radius[i] + pairs.radius[j];
    if (distance >= reach) continue;
    for (int a = 0; a < 3; ++a) closing += (pairs.v[3 * i + a] - pairs.v[3 * j + a]) * d[a] / distance;
    const double m_eff = pairs.mass[i] * pairs.mass[j] / (pairs.mass[i] + pairs.mass[j]);
    const ContactLaw::Result r = law.normal(reach - distance, -closing, m_eff);
    for (int a = 0; a < 3; ++a) expected[3 * p + a] = r.force * d[a] / distance;
    elastic += r.elastic;
    dissipated += r.dissipated;
    contacts += 1.0;
  }
  ASSERT_GT(contacts, 50.0);
  ASSERT_LT(contacts, static_cast<double>(count));
  // The kernel over ranges cut at odd places.
  std::vector<double> force(3 * count);
  PairTotals total;
  for (std::size_t begin = 0; begin < count;) {
    const std::size_t end = std::min(count, begin + 1 + (begin * 7 + 13) % 61);
    sweep.force = &force[3 * begin];
    const PairTotals t = normal_pair_forces(sweep, begin, end);
    total.elastic += t.elastic;
    total.dissipated += t.dissipated;
    total.contacts += t.contacts;
    begin = end;
  }
  double largest = 0.0;
  for (double f : expected) largest = std::max(largest, std::abs(f));
  for (std::size_t k = 0; k < 3 * count; ++k)
    ASSERT_NEAR(force[k], expected[k], 1e-12 * largest) << "pair " << k / 3 << ", component " << k % 3;
  EXPECT_EQ(total.contacts, contacts);
  EXPECT_NEAR(total.elastic, elastic, 1e-12 * elastic);
  EXPECT_NEAR(total.dissipated, dissipated, 1e-12 * dissipated);
}

TEST(PairKernel, SpringDashpotOfEqualSpheresMatchesTheLaw) {
  ContactLaw law;
  law.stiffness = 2000.0;
  law.damping = ContactLaw::lsd_damping_factor(0.5);
  expect_kernel_matches_law(law, false);
}

TEST(PairKernel, SpringDashpotOfUnequalSpheresMatchesTheLaw) {
  ContactLaw law;
  law.stiffness = 2000.0;
  law.damping = ContactLaw::lsd_damping_factor(0.3);
  expect_kernel_matches_law(law, true);
}

TEST(PairKernel, HertzMatchesTheLaw) {
  ContactLaw law;
  law.model = ContactModel::hertz;
  law.stiffness = 5000.0;
  law.damping = 1e-3;
  expect_kernel_matches_law(law, true);
  expect_kernel_matches_law(law, false);
}

}  // namespace
}  // namespace granflow::dem
