// The MDAnalysis view of a result: /particles/trajectory maps onto the
// result's frames (no copy), with steps, times and box, and /observables
// keeps the rows sampled at the frames' steps. MDAnalysis itself reads it
// in tests/interop.

#include "engine/io/mdanalysis_export.hpp"

#include <gtest/gtest.h>

#include "engine/core/input_error.hpp"
#include "engine/io/h5md_reader.hpp"
#include "small_result.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

TEST(MdanalysisExport, TheTrajectoryIsTheResultsFrames) {
  ScratchDirectory scratch("granflow_mdanalysis_export_test_");
  const std::string result = (scratch.path / "result.h5md").string(), out = (scratch.path / "result.md.h5").string();
  test::write_small_result(result);
  EXPECT_EQ(export_mdanalysis(result, out), 2u);
  const H5mdReader reader(out);
  EXPECT_EQ(reader.shape("/particles/trajectory/position/value"), (std::vector<std::uint64_t>{2, 3, 3}));
  const DoubleArray last = reader.frame("/particles/trajectory/position/value", 1);
  for (std::uint32_t k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(last.values[3 * k + a], test::position_of(k, 1)[a]);
  EXPECT_EQ(reader.integers("/particles/trajectory/position/step"), (std::vector<std::int64_t>{0, 10}));
  EXPECT_EQ(reader.doubles("/observables/kinetic_energy/value").values, (std::vector<double>{1.0, 2.0}));
}

}  // namespace
}  // namespace granflow
