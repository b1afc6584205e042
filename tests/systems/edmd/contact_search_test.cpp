// The vectorised contact search against the scalar contact_time() of
// collision_rule.hpp, candidate by candidate: every contact time bit for bit,
// the earliest and its position (ties to the first), over ranges that start
// and end inside groups, through periodic shifts, with the sentinel padding.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "systems/edmd/candidate_list.hpp"
#include "systems/edmd/collision_rule.hpp"
#include "systems/edmd/contact_search.hpp"

namespace granflow::edmd {
namespace {

template <int D>
struct Scene {
  std::vector<MotionRecord<D>> records;  // the last one is the sentinel
  std::vector<double> shifts;            // slot s at offset D * s; slot 0 is the zero shift
  MotionRecord<D> self;
  double now = 3.0;
};

template <int D>
Scene<D> make_scene(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> position(-2.0, 2.0), velocity(-1.0, 1.0), age(0.0, 0.5), radius(0.3, 0.6);
  Scene<D> scene;
  for (int k = 0; k < count; ++k) {
    MotionRecord<D> record;
    for (int a = 0; a < D; ++a) {
      record.x[a] = position(rng);
      record.v[a] = velocity(rng);
    }
    record.t = scene.now - age(rng);
    record.r = radius(rng);
    scene.records.push_back(record);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  scene.records.push_back({Vec<D>::Constant(nan), Vec<D>::Zero(), 0.0, 0.0});
  scene.shifts.assign(3 * D, 0.0);
  for (int a = 0; a < D; ++a) {
    scene.shifts[D + a] = a == 0 ? 4.0 : 0.0;  // one box length along the first axis
    scene.shifts[2 * D + a] = a == D - 1 ? -4.0 : 0.0;
  }
  scene.self.x = Vec<D>::Zero();
  for (int a = 0; a < D; ++a) scene.self.v[a] = velocity(rng);
  scene.self.t = scene.now;
  scene.self.r = 0.5;
  return scene;
}

// contact_time() for candidate k seen through the shift at `offset`,
// positions moved to `now` by the same operations as the search.
template <int D>
double reference_time(const Scene<D>& scene, int k, int offset) {
  const MotionRecord<D>& record = scene.records[static_cast<std::size_t>(k)];
  Vec<D> dx, dv;
  for (int a = 0; a < D; ++a) {
    double x = record.x[a] + record.v[a] * (scene.now - record.t);
    x += scene.shifts[static_cast<std::size_t>(offset + a)];
    dx[a] = x - scene.self.x[a];
    dv[a] = record.v[a] - scene.self.v[a];
  }
  return scene.now + contact_time<D>(dx, dv, scene.self.r + record.r);
}

// With images, candidates are seen through three shifts in turn; without,
// the list carries no shifts at all.
template <int D>
void check_against_reference(unsigned seed, bool images) {
  std::mt19937_64 rng(seed);
  const int count = 37;
  Scene<D> scene = make_scene<D>(rng, count);
  // Some candidates are listed twice, so that exactly equal times occur.
  CandidateList list;
  auto writer = list.refill(scene.records.data(), count, 0);
  std::vector<std::int32_t> order, offsets;
  for (int k = 0; k < count; ++k) {
    const std::int32_t offset = images ? D * static_cast<std::int32_t>(k % 3) : 0;
    for (int copy = 0; copy < (k % 11 == 5 ? 2 : 1); ++copy) {
      const auto end_of_list = [](std::uint32_t) { return -1; };
      if (images) writer.append_shifted_list(k, end_of_list, offset);
      else writer.append_list(k, end_of_list);
      order.push_back(k);
      offsets.push_back(offset);
    }
  }
  writer.close();
  ASSERT_EQ(list.size(), order.size());
  for (std::size_t begin : {0ul, 1ul, 3ul, 6ul}) {
    for (std::size_t end : {order.size(), order.size() - 1, order.size() - 5, begin + 2}) {
      const auto found = earliest_contact<D>(list, begin, end, scene.records.data(),
                                             images ? scene.shifts.data() : nullptr, 0, scene.self, scene.now);
      // The search may also test candidates of the groups the range touches,
      // never more: compare within those groups.
      const std::size_t first = begin / CandidateList::group * CandidateList::group;
      const std::size_t last = std::min(order.size(), (end + CandidateList::group - 1) / CandidateList::group *
                                                          CandidateList::group);
      double earliest = never;
      std::size_t position = first;
      for (std::size_t c = first; c < last; ++c) {
        const double t = reference_time<D>(scene, order[c], offsets[c]);
        EXPECT_EQ(list.times()[c], t) << "candidate " << c << " of [" << begin << ", " << end << ")";
        if (t < earliest) {
          earliest = t;
          position = c;
        }
      }
      EXPECT_EQ(found.time, earliest);
      if (earliest < never) {
        EXPECT_EQ(found.position, position);
        EXPECT_EQ(list.index<D>(found.position), static_cast<std::uint32_t>(order[position]));
      }
    }
  }
  // The padding of the last group is the sentinel, which never collides.
  for (std::size_t c = order.size(); c % CandidateList::group != 0; ++c) EXPECT_EQ(list.times()[c], never);
}

TEST(ContactSearch, MatchesTheScalarContactTimeIn3D) {
  for (unsigned seed = 1; seed <= 20; ++seed)
    for (const bool images : {true, false}) check_against_reference<3>(seed, images);
}

TEST(ContactSearch, MatchesTheScalarContactTimeIn2D) {
  for (unsigned seed = 1; seed <= 20; ++seed)
    for (const bool images : {true, false}) check_against_reference<2>(seed, images);
}

TEST(ContactSearch, OverlappingApproachingPairCollidesAtOnceAndRecedingPairNever) {
  Scene<3> scene;
  scene.shifts.assign(3, 0.0);
  scene.self = {Vec<3>::Zero(), Vec<3>::Zero(), scene.now, 0.5};
  // Overlapping by round-off and approaching; overlapping and receding.
  scene.records.push_back({Vec<3>(0.999, 0, 0), Vec<3>(-1, 0, 0), scene.now, 0.5});
  scene.records.push_back({Vec<3>(0, 0.999, 0), Vec<3>(0, 1, 0), scene.now, 0.5});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  scene.records.push_back({Vec<3>::Constant(nan), Vec<3>::Zero(), 0.0, 0.0});
  CandidateList list;
  auto writer = list.refill(scene.records.data(), 2, 0);
  writer.append_list(1, [](std::uint32_t) { return -1; });
  writer.append_list(0, [](std::uint32_t) { return -1; });
  writer.close();
  const auto found = earliest_contact<3>(list, 0, 2, scene.records.data(), nullptr, 0, scene.self, scene.now);
  EXPECT_EQ(found.time, scene.now);
  EXPECT_EQ(list.index<3>(found.position), 0u);
  EXPECT_EQ(list.times()[0], never);
}

}  // namespace
}  // namespace granflow::edmd
