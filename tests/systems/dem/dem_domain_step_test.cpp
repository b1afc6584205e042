// The soft-sphere step over MPI ranks (dem_domain_step.hpp) on a lone rank,
// against the one-rank chain it must reproduce bit for bit (its slower,
// simpler reference): a shaken bed with friction, whose lists are rebuilt
// from the migrated spheres and whose springs are carried by the pairs'
// ids rather than by the previous lists; observers of the part it lends
// see the chain's values; and a sphere driven through the
// floor stops the run with the one-rank diagnosis. The step over 2 and 3
// real ranks is tests/cli/dem_ranks_test.sh.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <numeric>
#include <vector>

#include "components/angular_velocity.hpp"
#include "components/box.hpp"
#include "components/clock.hpp"
#include "components/compartment_side.hpp"
#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/core/communicator.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/observed_part.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/dem/compartments.hpp"
#include "systems/dem/contact_forces.hpp"
#include "systems/dem/dem_domain_step.hpp"
#include "systems/dem/dem_energy.hpp"
#include "systems/dem/dem_setup.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/velocity_verlet.hpp"

namespace granflow::dem {
namespace {

// A ring of one rank: what goes down comes back from above.
class LoneRank final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  Received exchange_with_neighbours(int, const std::vector<double>& down, int, const std::vector<double>& up,
                                    int) const override {
    return {up, down};
  }
  std::vector<double> gather_all(const std::vector<double>& mine) const override { return mine; }
  std::int64_t sum(std::int64_t value) const override { return value; }
  bool from_first(bool value) const override { return value; }
};

constexpr double dt = 2e-4;

// 240 spheres with random velocities in a closed 6 x 6 x 16 box, the floor
// shaking, gravity, spring-dashpot contacts with Coulomb friction.
void make_bed(World& world, double kick_down = 0.0) {
  constexpr std::size_t n = 240;
  world.resize(n);
  world.emplace_resource<Clock>();
  world.emplace_resource<RunControl>();
  auto& x = world.add_component<Position<3>>();
  auto& v = world.add_component<Velocity<3>>();
  world.add_component<Force<3>>();
  world.add_component<Mass>().values.assign(n, 1.0);
  world.add_component<Radius>().values.assign(n, 0.5);
  auto& id = world.add_component<ParticleId>().values;
  id.resize(n);
  std::iota(id.begin(), id.end(), 0u);
  for (auto& w : world.add_component<AngularVelocity>().values) w.setZero();
  for (auto& t : world.add_component<Torque>().values) t.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = Vec<3>(0.75 + 1.1 * static_cast<double>(i % 5), 0.75 + 1.1 * static_cast<double>(i / 5 % 5),
                  0.75 + 1.1 * static_cast<double>(i / 25));
    Philox random(1, 7, 0, i);
    for (int a = 0; a < 3; ++a) v[i][a] = 2.0 * random.normal();
  }
  v[17][2] -= kick_down;
  auto& box = world.emplace_resource<Box<3>>();
  box.length = {6.0, 6.0, 16.0};
  ContactLaw law;
  law.stiffness = 2e4;
  law.damping = ContactLaw::lsd_damping_factor(0.7);
  auto& in = world.emplace_resource<DemInteractions<3>>();
  in.law = law;
  in.friction.mu = 0.5;
  in.friction.dt = dt;
  in.gravity = {0.0, 0.0, -1.0};
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, +1}) {
      DemWall w;
      w.axis = axis;
      w.side = side;
      w.rest = side < 0 ? 0.0 : box.length[static_cast<std::size_t>(axis)];
      w.law = law;
      if (axis == 2 && side < 0) {
        w.amplitude = 0.2;
        w.omega = 2.0 * std::numbers::pi * 3.0;
      }
      in.walls.push_back(w);
    }
  world.emplace_resource<DemWatch<3>>(wall_reach(box.length, box.periodic, in.walls)).advice = "ADVICE";
  auto& nl = world.emplace_resource<NeighbourList<3>>();
  nl.skin = 0.2;
  nl.reorder = true;
  nl.keeps_history = true;
  nl.walls = in.walls.size();
  world.emplace_resource<DemLedger>();
  DemNeighbourList<3>().run(world);
  DemContactForces<3>().run(world);
}

// The one-rank chain the step must reproduce.
struct OneRankChain {
  DemKickDrift<3> drift{dt};
  DemNeighbourList<3> lists;
  DemContactForces<3> forces;
  DemKick<3> kick{dt};
  void step(World& world) {
    drift.run(world);
    lists.run(world);
    forces.run(world);
    kick.run(world);
  }
};

DemDomainStep lone_step(const LoneRank& lone, const World& world) {
  return DemDomainStep(lone, dt, list_cells(world.resource<Box<3>>(), 1.0 + 0.2, world.size()), DemDomainBalance{});
}

TEST(DemDomainStep, OnALoneRankItIsTheOneRankChainBitForBit) {
  World chain, ranked;
  make_bed(chain);
  make_bed(ranked);
  OneRankChain one_rank;
  DemEnergyAccount<3> account(dt);
  const LoneRank lone;
  DemDomainStep step = lone_step(lone, ranked);
  for (int s = 0; s < 3000; ++s) {
    one_rank.step(chain);
    account.run(chain);
    step.run(ranked);
  }
  step.synchronise_host(ranked);
  const auto& nl = chain.resource<NeighbourList<3>>();
  ASSERT_GT(nl.builds, 20u) << "the lists must be rebuilt, and the springs carried, many times";
  ASSERT_GT(std::count_if(nl.shear.begin(), nl.shear.end(), [](const Shear& h) { return h[0] != 0.0; }), 10)
      << "springs must be loaded for the comparison to test their history";
  EXPECT_EQ(ranked.resource<NeighbourList<3>>().builds, nl.builds);
  for (std::size_t i = 0; i < chain.size(); ++i) {
    ASSERT_EQ(ranked.component<ParticleId>()[i], chain.component<ParticleId>()[i]) << "order at " << i;
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(ranked.component<Position<3>>()[i][a], chain.component<Position<3>>()[i][a]) << i;
      EXPECT_EQ(ranked.component<Velocity<3>>()[i][a], chain.component<Velocity<3>>()[i][a]) << i;
      EXPECT_EQ(ranked.component<AngularVelocity>()[i][a], chain.component<AngularVelocity>()[i][a]) << i;
    }
  }
  EXPECT_EQ(ranked.resource<NeighbourList<3>>().list, nl.list);
  for (std::size_t p = 0; p < nl.shear.size(); ++p) ASSERT_EQ(ranked.resource<NeighbourList<3>>().shear[p], nl.shear[p]) << p;
  EXPECT_EQ(ranked.resource<DemLedger>().injected, chain.resource<DemLedger>().injected);
  EXPECT_EQ(ranked.resource<DemLedger>().dissipated, chain.resource<DemLedger>().dissipated);
  EXPECT_EQ(ranked.resource<DemInteractions<3>>().elastic, chain.resource<DemInteractions<3>>().elastic);
}

// Observers over ranks see the rank's own spheres, lent to the World: the
// compartment sampler, whose sides travel with the spheres through the
// step's reorderings, and the energy observer, whose sums take the whole
// system's grouping, give the one-rank chain's values bit for bit.
TEST(DemDomainStep, ObserversOfTheLentPartSeeTheOneRankChainsValues) {
  World chain, ranked;
  make_bed(chain);
  make_bed(ranked);
  for (World* world : {&chain, &ranked}) {
    world->add_component<CompartmentSide>();
    auto& store = world->emplace_resource<ObservableStore>();
    for (const char* name : {"kinetic_energy", "potential_energy", "elastic_energy", "energy_injected",
                             "energy_dissipated", "contact_count", "coordination_number"})
      store.declare(name);
  }
  OneRankChain one_rank;
  const LoneRank lone;
  DemDomainStep step = lone_step(lone, ranked);
  const auto chain_counts = std::make_shared<CompartmentCounts>(), ranked_counts = std::make_shared<CompartmentCounts>();
  CompartmentSampler<3> chain_sampler(0, 3.0, chain_counts), ranked_sampler(0, 3.0, ranked_counts);
  DemEnergyObserver<3> energy;
  const auto observe = [&](World& world, CompartmentSampler<3>& sampler) {
    sampler.run(world);
    energy.run(world);
    return world.resource<ObservableStore>();
  };
  for (int s = 0; s < 1500; ++s) {
    one_rank.step(chain);
    step.run(ranked);
    ObservableStore alone = observe(chain, chain_sampler);
    ASSERT_TRUE(step.lend_part(ranked)) << "step " << s;
    ASSERT_EQ(ranked.size(), chain.size());
    ObservableStore lent = observe(ranked, ranked_sampler);
    ranked.emplace_resource<ObservedPart>();
    step.take_back_part(ranked);
    for (const char* name : {"kinetic_energy", "potential_energy", "elastic_energy", "coordination_number"})
      ASSERT_EQ(lent.scalar(name), alone.scalar(name)) << name << " at step " << s;
  }
  EXPECT_GT(chain_counts->left_to_right, 2.0) << "spheres must cross the divider for the sides to be tested";
  EXPECT_GT(chain_counts->right_to_left, 2.0);
  EXPECT_EQ(ranked_counts->left_to_right, chain_counts->left_to_right);
  EXPECT_EQ(ranked_counts->right_to_left, chain_counts->right_to_left);
}

TEST(DemDomainStep, ASphereThroughTheFloorStopsTheRunAsOnOneRank) {
  World chain, ranked;
  make_bed(chain, 2000.0);
  make_bed(ranked, 2000.0);
  OneRankChain one_rank;
  const LoneRank lone;
  DemDomainStep step = lone_step(lone, ranked);
  for (int s = 0; s < 20 && !chain.resource<RunControl>().stop; ++s) {
    one_rank.step(chain);
    step.run(ranked);
  }
  const auto& failed = ranked.resource<RunControl>();
  ASSERT_TRUE(chain.resource<RunControl>().failed);
  ASSERT_TRUE(failed.failed);
  EXPECT_NE(failed.reason.find("sphere 17 went through a wall: z = "), std::string::npos) << failed.reason;
  EXPECT_EQ(failed.reason, chain.resource<RunControl>().reason);
}

}  // namespace
}  // namespace granflow::dem
