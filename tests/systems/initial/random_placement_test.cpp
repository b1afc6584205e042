// Random placement: no overlaps (checked against all pairs), particles inside
// the walls, reproducible from the seed, and a clear error when the packing
// fraction cannot be reached.

#include <gtest/gtest.h>

#include "systems/initial/random_placement.hpp"

namespace granflow {
namespace {

template <int D>
void expect_valid_placement(bool periodic, double eta) {
  Box<D> box;
  box.length.fill(1.0);
  box.periodic.fill(periodic);
  PlacementRegion<D> region;
  region.upper = box.length;
  const std::size_t n = 2000;
  const double r = D == 3 ? std::cbrt(eta * 3 / (4 * std::numbers::pi * n)) : std::sqrt(eta / (std::numbers::pi * n));
  const std::vector<double> radii(n, r);
  const auto x = place_randomly<D>(box, region, radii, 1);
  EXPECT_EQ(x, place_randomly<D>(box, region, radii, 1));
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) {
      EXPECT_GE(x[i][a], periodic ? 0.0 : r);
      EXPECT_LE(x[i][a], periodic ? 1.0 : 1.0 - r);
    }
    for (std::size_t j = i + 1; j < n; ++j) {
      Vec<D> dx = x[j] - x[i];
      if (periodic)
        for (int a = 0; a < D; ++a) dx[a] -= std::round(dx[a]);
      ASSERT_GE(dx.norm(), 2 * r) << i << " overlaps " << j;
    }
  }
}

TEST(RandomPlacement, NoOverlaps2D) {
  expect_valid_placement<2>(true, 0.4);
  expect_valid_placement<2>(false, 0.4);
}
TEST(RandomPlacement, NoOverlaps3D) {
  expect_valid_placement<3>(true, 0.25);
  expect_valid_placement<3>(false, 0.25);
}

TEST(RandomPlacement, ImpossiblePackingIsRefusedWithReason) {
  Box<3> box;
  box.length.fill(1.0);
  PlacementRegion<3> region;
  region.upper = box.length;
  const std::vector<double> radii(1000, 0.06);  // packing fraction 0.90
  try {
    place_randomly<3>(box, region, radii, 1);
    FAIL() << "expected an error";
  } catch (const PlacementError& e) {
    EXPECT_NE(std::string(e.what()).find("packing fraction 0.9048"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace granflow
