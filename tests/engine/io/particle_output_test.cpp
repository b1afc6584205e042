// The particle schema: whatever order the engine keeps particles in, rows
// are written in particle-id order.

#include "engine/io/particle_output.hpp"

#include <gtest/gtest.h>

#include "small_result.hpp"

namespace granflow {
namespace {

TEST(ParticleOutput, StorageOrderMapsIdsToStorageIndices) {
  const World world = test::small_world();
  const auto order = storage_order(ParticleConstantsView(world));
  EXPECT_EQ(order, (std::vector<std::uint32_t>{2, 0, 1}));
  World without_ids;
  without_ids.resize(4);
  without_ids.add_component<Mass>();
  EXPECT_EQ(storage_order(ParticleConstantsView(without_ids)), (std::vector<std::uint32_t>{0, 1, 2, 3}));
}

TEST(ParticleOutput, ColumnsFlattenInIdOrder) {
  World world = test::small_world();
  const auto order = storage_order(ParticleConstantsView(world));
  EXPECT_EQ(flatten_by_id(world.component<Mass>(), order), (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(flatten_integers_by_id(world.component<Species>(), order), (std::vector<std::int32_t>{0, 0, 1}));
  EXPECT_EQ(flatten_integers_by_id(world.component<ImageCount<3>>(), order),
            (std::vector<std::int32_t>{0, 0, -1, 1, 0, -1, 2, 0, -1}));
  auto& x = world.component<Position<3>>();
  for (std::uint32_t k = 0; k < 3; ++k) x[test::stored_index[k]] = test::position_of(k, 0);
  const auto flat = flatten_by_id(x, order);
  ASSERT_EQ(flat.size(), 9u);
  for (std::uint32_t k = 0; k < 3; ++k) EXPECT_EQ(flat[3 * k + 1], test::position_of(k, 0)[1]);
}

}  // namespace
}  // namespace granflow
