// The calendar against an exact ordered set: the same earliest event after
// every operation, through random schedules, cancellations and a rate that
// falls by many orders of magnitude (a cooling gas).

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "systems/edmd/event_calendar.hpp"

namespace granflow::edmd {
namespace {

TEST(EventCalendar, MatchesAnOrderedSetThroughCooling) {
  constexpr std::uint32_t particles = 2000;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> times(particles);
  double now = 0.0, mean_interval = 1.0;
  for (auto& t : times) t = now + mean_interval * -std::log(unit(random));
  EventCalendar calendar(particles);
  calendar.rebuild(now, times);
  std::set<std::pair<double, std::uint32_t>> exact;
  for (std::uint32_t i = 0; i < particles; ++i) exact.insert({times[i], i});

  for (int step = 0; step < 400000; ++step) {
    const std::uint32_t first = calendar.earliest();
    ASSERT_EQ(first, exact.begin()->second) << "step " << step;
    now = times[first];
    // Events get rarer as the "gas" cools: the interval grows 10^4-fold.
    mean_interval *= 1.0 + 2.5e-5;
    const auto reschedule = [&](std::uint32_t i) {
      exact.erase({times[i], i});
      times[i] = unit(random) < 0.01 ? INFINITY : now + mean_interval * -std::log(unit(random));
      if (std::isfinite(times[i])) exact.insert({times[i], i});
      calendar.schedule(i, times[i]);
    };
    reschedule(first);
    const auto partner = static_cast<std::uint32_t>(unit(random) * particles);
    if (std::isfinite(times[partner]) || unit(random) < 0.5) reschedule(partner);
    ASSERT_EQ(calendar.size(), exact.size());
  }
  EXPECT_GT(mean_interval, 1e4);
}

TEST(EventCalendar, EqualTimesComeOutInIndexOrder) {
  EventCalendar calendar(5);
  calendar.rebuild(0.0, {2.0, 1.0, 1.0, INFINITY, 1.0});
  EXPECT_EQ(calendar.earliest(), 1u);
  calendar.unschedule(1);
  EXPECT_EQ(calendar.earliest(), 2u);
  calendar.unschedule(2);
  EXPECT_EQ(calendar.earliest(), 4u);
  calendar.unschedule(4);
  EXPECT_EQ(calendar.earliest(), 0u);
  calendar.unschedule(0);
  EXPECT_EQ(calendar.earliest(), EventCalendar::none);
}

// Hundreds of events at one time fill one bucket: it is then kept in heap
// order, and events filed into it meanwhile, at that very time or just
// after, must still come out in time and index order.
TEST(EventCalendar, ABurstOfEqualTimesComesOutInOrder) {
  constexpr std::uint32_t particles = 1000;
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> times(particles);
  for (std::uint32_t i = 0; i < particles; ++i) times[i] = i % 5 < 3 ? 1.0 : 3.0 * unit(random);
  EventCalendar calendar(particles);
  calendar.rebuild(0.0, times);
  std::set<std::pair<double, std::uint32_t>> exact;
  for (std::uint32_t i = 0; i < particles; ++i) exact.insert({times[i], i});
  for (int step = 0; step < 20000; ++step) {
    const std::uint32_t first = calendar.earliest();
    ASSERT_EQ(first, exact.begin()->second) << "step " << step;
    const double now = times[first];
    const auto reschedule = [&](std::uint32_t i, double t) {
      exact.erase({times[i], i});
      times[i] = t;
      exact.insert({t, i});
      calendar.schedule(i, t);
    };
    // A quarter of the events recur at once, as in a burst of contacts.
    reschedule(first, unit(random) < 0.25 ? now : now + 3.0 * unit(random));
    const auto partner = static_cast<std::uint32_t>(unit(random) * particles);
    if (unit(random) < 0.3) reschedule(partner, now + 1e-3 * unit(random));
    ASSERT_EQ(calendar.size(), exact.size());
  }
}

}  // namespace
}  // namespace granflow::edmd
