// When two declarations conflict: the Schedule's edges come from this alone.

#include "engine/core/access.hpp"

#include <gtest/gtest.h>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/units.hpp"

namespace granflow {
namespace {

TEST(Access, AWriteConflictsWithAReadOrWriteOfTheSameColumnOnly) {
  const Access drift = Access{}.reads<Velocity<3>>().writes<Position<3>>();
  const Access reader = Access{}.reads<Position<3>>();
  const Access other = Access{}.writes<Mass>();
  const Access also_reads_velocity = Access{}.reads<Velocity<3>>();
  EXPECT_TRUE(accesses_conflict(drift, reader));
  EXPECT_TRUE(accesses_conflict(reader, drift));
  EXPECT_TRUE(accesses_conflict(drift, drift));
  EXPECT_FALSE(accesses_conflict(drift, other));
  EXPECT_FALSE(accesses_conflict(drift, also_reads_velocity));  // two reads never conflict
}

TEST(Access, ObservablesConflictByNameAndTheWholeStoreWithEachName) {
  const Access kinetic = Access{}.writes_observable("kinetic_energy", unit::energy);
  const Access msd = Access{}.writes_observable("msd", unit::area);
  const Access kinetic_reader = Access{}.reads_observable("kinetic_energy");
  const Access whole_store = Access{}.reads<ObservableStore>();
  EXPECT_FALSE(accesses_conflict(kinetic, msd));
  EXPECT_TRUE(accesses_conflict(kinetic, kinetic_reader));
  EXPECT_FALSE(accesses_conflict(msd, kinetic_reader));
  EXPECT_TRUE(accesses_conflict(msd, whole_store));
}

TEST(Access, ReorderingConflictsWithEveryColumnButNoResource) {
  const Access sort = Access{}.writes_every_component();
  EXPECT_TRUE(accesses_conflict(sort, Access{}.reads<Mass>()));
  EXPECT_TRUE(accesses_conflict(sort, Access{}.reads<Position<2>>()));
  EXPECT_FALSE(accesses_conflict(sort, Access{}.writes<Clock>()));
  EXPECT_FALSE(accesses_conflict(sort, Access{}.writes_observable("msd")));
}

TEST(Access, WrittenObservablesAndTheirUnitsAreListedInOrder) {
  Access access;
  access.reads<Clock>().writes_observable("a", unit::time).writes_observable("b");
  access.writes<Mass>();
  EXPECT_EQ(access.written_observables(), (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(access.observable_units().size(), 1u);  // "b" gives none: another system declares it
  EXPECT_EQ(access.observable_units()[0], (std::pair<std::string, std::string>{"a", unit::time}));
  EXPECT_EQ(access.write_keys().back().label, Mass::key);
  EXPECT_EQ(access.write_keys()[0].label, std::string(ObservableStore::key) + ":a");
}

}  // namespace
}  // namespace granflow
