// A checkpoint's state is named arrays of doubles: prefixes nest states,
// texts and fixed-size vectors flatten into arrays and come back exactly.

#include "engine/core/state_map.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>

namespace granflow {
namespace {

TEST(StateMap, PrefixesNestAndUnnestStates) {
  StateMap whole{{"other", {9.0}}};
  put_state_under(whole, "gas", {{"time", {1.5}}, {"count", {1, 2, 3}}});
  put_state_under(whole, "gas_b", {{"time", {2.5}}});  // a longer name with the same start stays apart
  EXPECT_EQ(whole.at("gas/time"), std::vector<double>{1.5});
  const StateMap gas = state_under(whole, "gas");
  EXPECT_EQ(gas, (StateMap{{"time", {1.5}}, {"count", {1, 2, 3}}}));
  EXPECT_TRUE(state_under(whole, "none").empty());
}

TEST(StateMap, TextsRoundTripThroughBytes) {
  const std::vector<std::string> texts{"granflow run x.toml --set a=1", "", "höst"};
  EXPECT_EQ(decode_texts(encode_texts(texts)), texts);
  EXPECT_THROW(decode_texts({65.0, 256.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(decode_texts({-1.0, 0.0}), std::invalid_argument);
}

TEST(StateMap, VectorsRoundTripAndAWrongSizeIsNamed) {
  const std::vector<Eigen::Vector3d> vectors{Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(-4, 0.5, 1e300)};
  const std::vector<double> flat = flatten_vectors(vectors);
  EXPECT_EQ(flat, (std::vector<double>{1, 2, 3, -4, 0.5, 1e300}));
  std::vector<Eigen::Vector3d> back(2);
  unflatten_vectors(flat, back, "origins");
  EXPECT_EQ(back, vectors);
  std::vector<Eigen::Vector3d> three(3);
  try {
    unflatten_vectors(flat, three, "MSD origins");
    FAIL() << "a short array was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "checkpoint MSD origins has 6 values, expected 9");
  }
}

}  // namespace
}  // namespace granflow
