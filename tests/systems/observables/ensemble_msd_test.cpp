// The ensemble MSD reducer on hand-made run histories: means and standard
// errors over runs at each time and lag, the lag scaled to time, and the
// largest deviation from theory in standard errors.

#include "systems/observables/ensemble_msd.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace granflow {
namespace {

struct Member {
  ObservableHistory history;
};
struct Runs {
  std::vector<Member> members;
};

Member run(const std::vector<double>& msd, const std::vector<double>& time_averaged, double eb) {
  Member m;
  for (std::size_t k = 0; k < msd.size(); ++k) m.history["msd"].push_back({static_cast<std::int64_t>(k), 0.1 * k, {msd[k]}});
  std::vector<double> lags;
  for (std::size_t k = 0; k < time_averaged.size(); ++k) lags.push_back(static_cast<double>(k + 1));
  m.history["time_averaged_msd_lag"].push_back({9, 0.9, lags});
  m.history["time_averaged_msd"].push_back({9, 0.9, time_averaged});
  m.history["ergodicity_breaking"].push_back({9, 0.9, std::vector<double>(time_averaged.size(), eb)});
  return m;
}

TEST(EnsembleMsd, MeansAndStandardErrorsOverRuns) {
  Runs runs{{run({1.0, 4.0}, {0.5, 1.0}, 0.1), run({3.0, 6.0}, {1.5, 2.0}, 0.3), run({2.0, 8.0}, {1.0, 3.0}, 0.2)}};
  const auto r = reduce_ensemble_msd(runs, {0.1, 0.2}, {2.0, 5.0}, 0.25);
  ASSERT_EQ(r.msd.size(), 2u);
  EXPECT_DOUBLE_EQ(r.msd[0], 2.0);
  EXPECT_DOUBLE_EQ(r.msd_stderr[0], std::sqrt(1.0 / 3.0));  // sample variance 1 over 3 runs
  EXPECT_DOUBLE_EQ(r.msd[1], 6.0);
  EXPECT_DOUBLE_EQ(r.msd_stderr[1], std::sqrt(4.0 / 3.0));
  ASSERT_EQ(r.lag.size(), 2u);
  EXPECT_DOUBLE_EQ(r.lag[1], 0.5);  // lag 2 of 0.25
  EXPECT_DOUBLE_EQ(r.time_averaged_msd[0], 1.0);
  EXPECT_DOUBLE_EQ(r.time_averaged_msd[1], 2.0);
  EXPECT_DOUBLE_EQ(r.time_averaged_msd_stderr[1], std::sqrt(1.0 / 3.0));
  EXPECT_NEAR(r.ergodicity_breaking[0], 0.2, 1e-15);
  // |2 - 2| / 0.577 and |6 - 5| / 1.155: the second.
  EXPECT_DOUBLE_EQ(largest_deviation_in_standard_errors(r), 1.0 / std::sqrt(4.0 / 3.0));
}

TEST(EnsembleMsd, NoLagsWithoutATimeAverage) {
  Runs runs{{run({1.0}, {}, 0.0), run({3.0}, {}, 0.0)}};
  for (auto& m : runs.members) m.history.erase("time_averaged_msd_lag");
  const auto r = reduce_ensemble_msd(runs, {0.1}, {2.0}, 1.0);
  EXPECT_DOUBLE_EQ(r.msd[0], 2.0);
  EXPECT_TRUE(r.lag.empty());
}

}  // namespace
}  // namespace granflow
