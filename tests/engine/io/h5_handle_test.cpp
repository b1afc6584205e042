// An HDF5 identifier closed exactly once, whoever holds it last; a failed
// call becomes an H5Error naming what was attempted.

#include "engine/io/h5_handle.hpp"

#include <gtest/gtest.h>

namespace granflow {
namespace {

TEST(H5Handle, ClosesOnceWhenItsLastOwnerGoes) {
  hid_t id = -1;
  {
    H5Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create space");
    id = space.get();
    EXPECT_GT(H5Iis_valid(id), 0);
    H5Handle moved(std::move(space));
    EXPECT_FALSE(space.valid());  // NOLINT(bugprone-use-after-move): the point of the test
    EXPECT_EQ(moved.get(), id);
    H5Handle assigned;
    assigned = std::move(moved);
    EXPECT_GT(H5Iis_valid(id), 0);
  }
  EXPECT_LE(H5Iis_valid(id), 0);
}

TEST(H5Handle, FailuresNameWhatWasAttempted) {
  h5_quiet();
  try {
    H5Handle file(H5Fopen("/nonexistent/file.h5", H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open '/nonexistent/file.h5'");
    FAIL();
  } catch (const H5Error& error) {
    EXPECT_STREQ(error.what(), "HDF5 error: open '/nonexistent/file.h5'");
  }
  EXPECT_THROW(h5_check(-1, "write"), H5Error);
  EXPECT_NO_THROW(h5_check(0, "write"));
}

}  // namespace
}  // namespace granflow
