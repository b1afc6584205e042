// Dense initial states: the lattice holds any packing fraction up to the
// densest the lattice allows without overlaps, and the elastic run melts it
// into the equilibrium hard-sphere fluid — no Bragg peak of the lattice is
// left, and the collision rate is Enskog's with the Carnahan-Starling
// contact value, which a solid or a jammed state would miss.

#include <gtest/gtest.h>

#include <cmath>

#include "systems/initial/lattice_placement.hpp"
#include "tests/scenario_schema.hpp"
#include "tests/systems/initial/dense_fluid_checks.hpp"

namespace granflow {
namespace {

template <int D>
void expect_valid_packing(const Box<D>& box, std::size_t count, double eta) {
  double volume = 1.0;
  for (int a = 0; a < D; ++a) volume *= box.length[a];
  const double radius = theory::radius_for_packing_fraction<D>(static_cast<double>(count), eta, volume);
  const auto x = place_on_lattice<D>(box, count, radius, 7).positions;
  ASSERT_EQ(x.size(), count);
  for (const auto& p : x)
    for (int a = 0; a < D; ++a) {
      const double margin = box.periodic[a] ? 0.0 : radius;
      EXPECT_GE(p[a], margin);
      EXPECT_LE(p[a], box.length[a] - margin);
    }
  EXPECT_GE(testing::closest_relative<D>(x, std::vector<double>(count, radius), box), 1 - 1e-12) << "eta " << eta;
}

TEST(LatticePlacement, HoldsDenseFluidsWithoutOverlap) {
  Box<3> periodic;
  periodic.length = {1.0, 1.0, 1.0};
  periodic.periodic = {true, true, true};
  for (double eta : {0.05, 0.3, 0.45, 0.5}) expect_valid_packing<3>(periodic, 1000, eta);
  // Counts just above what a cubic grid holds need fewer rows along some axes.
  for (std::size_t count : {501, 865, 4001}) expect_valid_packing<3>(periodic, count, 0.5);
  Box<3> walls = periodic;
  walls.periodic = {false, false, false};
  for (double eta : {0.3, 0.45}) expect_valid_packing<3>(walls, 1000, eta);
  Box<2> square;
  square.length = {1.0, 1.0};
  square.periodic = {true, true};
  for (double eta : {0.3, 0.6, 0.7}) expect_valid_packing<2>(square, 900, eta);
  square.periodic = {false, false};
  expect_valid_packing<2>(square, 900, 0.5);
}

TEST(LatticePlacement, RefusesWhatTheLatticeCannotHold) {
  // Face-centred cubic packing is at most pi / sqrt(18) = 0.7405.
  Box<3> box;
  box.length = {1.0, 1.0, 1.0};
  box.periodic = {true, true, true};
  const double radius = theory::radius_for_packing_fraction<3>(1000.0, 0.76, 1.0);
  EXPECT_THROW(place_on_lattice<3>(box, 1000, radius, 1), PlacementError);
}

TEST(LatticePlacement, MeltsIntoTheEquilibriumFluid) {
  constexpr std::size_t count = 2000;  // 1000 cubic cells of 4 sites: 2048 sites, 48 vacancies
  constexpr double eta = 0.45;
  const Config config = testing::dense_gas_config(count, eta, "lattice");

  Box<3> box;
  box.length = {1.0, 1.0, 1.0};
  box.periodic = {true, true, true};
  const auto lattice = place_on_lattice<3>(box, count, config.real("system.radius"), 1);
  EXPECT_NEAR(structure_factor<3>(lattice.positions, lattice.bragg_vector), static_cast<double>(count), 1e-6 * count);

  World world;
  edmd::build_gas<3>(world, config, 1);
  EXPECT_LT(structure_factor<3>(world.component<Position<3>>().values, lattice.bragg_vector), 20.0);
  // Carnahan-Starling's contact value is within 1 % of simulation at this
  // density; 2 * 10^4 collisions average the rate to well under 1 %, and
  // the N = 2000 box shifts it by less: 4 % separates the fluid from a
  // crystal or a state still carrying the lattice.
  EXPECT_NEAR(testing::collision_rate_over_enskog(world, eta), 1.0, 0.04);
}

TEST(LatticePlacement, RefusesACrystalThatDoesNotMelt) {
  // Above 0.545 the hard-sphere crystal is the stable phase: it never melts.
  Config config(scenario_schema("haff_cooling"));
  config.set("system.count", std::int64_t{500});
  config.set("system.radius", theory::radius_for_packing_fraction<3>(500.0, 0.56, 1.0));
  config.set("initial.placement", std::string("lattice"));
  config.set("initial.velocity", std::string("maxwell_boltzmann"));
  World world;
  try {
    edmd::build_gas<3>(world, config, 1);
    FAIL() << "a crystal was taken for a fluid";
  } catch (const PlacementError& e) {
    EXPECT_NE(std::string(e.what()).find("has not melted"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace granflow
