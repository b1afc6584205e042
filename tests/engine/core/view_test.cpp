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

}  // namespace
}  // namespace granflow
