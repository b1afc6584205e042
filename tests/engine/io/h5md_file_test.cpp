// What a run writes, read back: observables with their units, particle
// constants and frames in id order, the box, results and attributes; a file
// appears only when finished, and one output is never written by two runs.

#include "engine/io/h5md_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "engine/core/input_error.hpp"
#include "engine/core/units.hpp"
#include "engine/io/h5md_reader.hpp"
#include "small_result.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

TEST(H5mdFile, ParticlesObservablesAndBoxReadBackInIdOrder) {
  ScratchDirectory scratch("granflow_h5md_file_test_");
  const std::string path = (scratch.path / "result.h5md").string();
  test::write_small_result(path);
  const H5mdReader reader(path);
  EXPECT_EQ(reader.shape("/particles/all/position/value"), (std::vector<std::uint64_t>{2, 3, 3}));
  const DoubleArray last = reader.frame("/particles/all/position/value", 1);
  for (std::uint32_t k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(last.values[3 * k + a], test::position_of(k, 1)[a]) << "id " << k;
  EXPECT_EQ(reader.integers("/particles/all/position/step"), (std::vector<std::int64_t>{0, 10}));
  EXPECT_EQ(reader.doubles("/particles/all/position/time").values, (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(reader.doubles("/particles/all/mass").values, (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(reader.integers("/particles/all/species"), (std::vector<std::int64_t>{0, 0, 1}));
  EXPECT_EQ(reader.integers("/particles/all/id"), (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(reader.string_attribute("/particles/all/mass", "unit"), unit::mass);
  const auto image = reader.frame("/particles/all/image/value", 0).values;
  EXPECT_EQ(image, (std::vector<double>{0, 0, -1, 1, 0, -1, 2, 0, -1}));
  EXPECT_EQ(reader.doubles("/observables/kinetic_energy/value").values, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(reader.string_list_attribute("/particles/all/box", "boundary"),
            (std::vector<std::string>{"periodic", "periodic", "periodic"}));
  // Each frame's box as the matrix of its edge vectors, as MDAnalysis reads it.
  EXPECT_EQ(reader.frame("/particles/all/box/edges/value", 1).values,
            (std::vector<double>{2.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 4.0}));
  EXPECT_EQ(reader.integer_attribute("/particles/all/box", "dimension"), 3);
}

TEST(H5mdFile, UnitsResultsAndAttributesAreWritten) {
  ScratchDirectory scratch("granflow_h5md_file_test_");
  const std::string path = (scratch.path / "units.h5md").string();
  {
    H5mdFile file(path, "io_test");
    file.declare_unit("msd", unit::area);
    file.append_observable("msd", 1, 0.1, 0.25);
    file.append_observable("profile", 1, 0.1, std::vector<double>{1.0, 2.0, 3.0});
    file.write_result("speed_histogram", {0.5, 1.5}, unit::per_velocity);
    file.write_attribute("/observables", "note", "a text");
    file.write_attribute("/observables", "layer", 0.75);
    file.finish();
  }
  const H5mdReader reader(path);
  EXPECT_EQ(reader.string_attribute("/observables/msd/value", "unit"), unit::area);
  EXPECT_EQ(reader.string_attribute("/observables/msd/time", "unit"), unit::time);
  EXPECT_EQ(reader.shape("/observables/profile/value"), (std::vector<std::uint64_t>{1, 3}));
  EXPECT_EQ(reader.doubles("/results/speed_histogram").values, (std::vector<double>{0.5, 1.5}));
  EXPECT_EQ(reader.string_attribute("/observables", "note"), "a text");
  EXPECT_EQ(reader.double_attribute("/observables", "layer"), 0.75);
  EXPECT_TRUE(reader.exists("/h5md"));
  EXPECT_TRUE(reader.exists("/provenance"));
}

TEST(H5mdFile, AFileAppearsOnlyWhenFinished) {
  ScratchDirectory scratch("granflow_h5md_file_test_");
  const std::string path = (scratch.path / "abandoned.h5md").string();
  {
    H5mdFile file(path, "io_test");
    file.append_observable("x", 0, 0.0, 1.0);
    EXPECT_TRUE(std::filesystem::exists(path + ".partial"));
  }  // a run that threw: never finished
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
}

TEST(H5mdFile, ASecondWriterOfTheSameOutputIsRefused) {
  ScratchDirectory scratch("granflow_h5md_file_test_");
  const std::string path = (scratch.path / "shared.h5md").string();
  H5mdFile first(path, "io_test");
  try {
    H5mdFile second(path, "io_test");
    FAIL() << "two writers of one file";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("in use by another run"), std::string::npos) << error.what();
  }
  first.finish();
  EXPECT_TRUE(std::filesystem::exists(path));
}

// A frame written in blocks of rows, in any order (as over ranks), reads
// back as the same frame written whole; a frame too large for one chunk too.
TEST(H5mdFile, AFrameWrittenInBlocksOfRowsIsTheWholeFrame) {
  ScratchDirectory scratch("granflow_h5md_file_test_");
  const std::string path = (scratch.path / "blocks.h5md").string();
  const std::size_t rows = 500000;  // 1.5e6 values: chunked by particles
  std::vector<double> position(3 * rows);
  for (std::size_t k = 0; k < position.size(); ++k) position[k] = 0.25 * static_cast<double>(k);
  std::vector<std::int32_t> image(3 * rows);
  for (std::size_t k = 0; k < image.size(); ++k) image[k] = static_cast<std::int32_t>(k % 7) - 3;
  {
    H5mdFile file(path, "io_test");
    file.append_particle_frame("position", 0, 0.0, position, 3);
    file.begin_particle_frame("position", 5, 0.5, rows, 3, false);
    file.write_particle_rows("position", 300000, rows - 300000, position.data() + 3 * 300000);
    file.write_particle_rows("position", 0, 300000, position.data());
    file.begin_particle_frame("image", 5, 0.5, rows, 3, true);
    file.write_particle_rows("image", 7, rows - 7, image.data() + 21);
    file.write_particle_rows("image", 0, 7, image.data());
    EXPECT_EQ(file.particles_in_frames("position"), rows);
    EXPECT_EQ(file.particles_in_frames("velocity"), 0u);
    file.finish();
  }
  const H5mdReader reader(path);
  EXPECT_EQ(reader.shape("/particles/all/position/value"), (std::vector<std::uint64_t>{2, rows, 3}));
  EXPECT_EQ(reader.frame("/particles/all/position/value", 1).values, position);
  EXPECT_EQ(reader.frame("/particles/all/position/value", 0).values, position);
  EXPECT_EQ(reader.integers("/particles/all/position/step"), (std::vector<std::int64_t>{0, 5}));
  const auto read_image = reader.frame("/particles/all/image/value", 0).values;
  EXPECT_EQ(std::vector<double>(image.begin(), image.end()), read_image);
  EXPECT_EQ(reader.string_attribute("/particles/all/position/value", "unit"), unit::length);
}

}  // namespace
}  // namespace granflow
