// A View hands out what it lists, and its access() is exactly that list;
// reading what it does not list does not compile (view_undeclared_read.cpp,
// the ctest view_undeclared_read_test).

#include "engine/core/view.hpp"

#include <gtest/gtest.h>

#include <typeindex>

#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"

namespace granflow {
namespace {

using Drift = View<Reads<Velocity<2>, Mass>, Writes<Position<2>>>;

TEST(View, AccessIsTheListedTypes) {
  const Access access = Drift::access();
  ASSERT_EQ(access.read_keys().size(), 2u);
  EXPECT_EQ(access.read_keys()[0].type, std::type_index(typeid(Velocity<2>)));
  EXPECT_EQ(access.read_keys()[1].type, std::type_index(typeid(Mass)));
  ASSERT_EQ(access.write_keys().size(), 1u);
  EXPECT_EQ(access.write_keys()[0].type, std::type_index(typeid(Position<2>)));
}

TEST(View, ReadsAndWritesTheWorldsColumns) {
  World world;
  world.resize(2);
  world.add_component<Velocity<2>>().values = {Vec<2>(1.0, 0.0), Vec<2>(0.0, 2.0)};
  world.add_component<Position<2>>().values = {Vec<2>::Zero(), Vec<2>::Zero()};
  Drift view(world);
  EXPECT_FALSE(view.has<Mass>());
  for (std::size_t i = 0; i < view.size(); ++i) view.write<Position<2>>()[i] += 0.5 * view.read<Velocity<2>>()[i];
  EXPECT_EQ(world.component<Position<2>>()[1], Vec<2>(0.0, 1.0));
  // What a view writes it may read too.
  EXPECT_EQ(&view.read<Position<2>>(), &world.component<Position<2>>());
}

// A helper that declares less than its caller: the caller's view narrows to it.
double total_speed(const View<Reads<Velocity<2>>, Writes<>>& view) {
  double sum = 0.0;
  for (std::size_t i = 0; i < view.size(); ++i) sum += view.read<Velocity<2>>()[i].norm();
  return sum;
}

TEST(View, NarrowsToAHelpersViewOfTheSameWorld) {
  World world;
  world.resize(2);
  world.add_component<Velocity<2>>().values = {Vec<2>(3.0, 4.0), Vec<2>(0.0, 2.0)};
  world.add_component<Position<2>>().values = {Vec<2>::Zero(), Vec<2>::Zero()};
  Drift view(world);
  EXPECT_DOUBLE_EQ(total_speed(view), 7.0);
  // A World converts too: setup code hands it to the same helpers.
  EXPECT_DOUBLE_EQ(total_speed(world), 7.0);
}

TEST(View, EveryColumnDeclaresAReorderingAndMayPermute) {
  using Sorter = View<Reads<>, Writes<EveryColumn>>;
  const Access access = Sorter::access();
  ASSERT_EQ(access.write_keys().size(), 1u);
  EXPECT_EQ(access.write_keys()[0].kind, AccessKey::Kind::every_component);
  World world;
  world.resize(3);
  world.add_component<Mass>().values = {1.0, 2.0, 3.0};
  Sorter sorter(world);
  sorter.permute({2, 0, 1});
  // Any column may be read and written through it.
  EXPECT_EQ(sorter.read<Mass>().values, (std::vector<double>{3.0, 1.0, 2.0}));
  sorter.write<Mass>()[0] = 4.0;
  EXPECT_EQ(world.component<Mass>()[0], 4.0);
}

}  // namespace
}  // namespace granflow
