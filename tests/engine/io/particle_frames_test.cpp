// What the exporters learn of a result file's frames: counts, times, box,
// periodicity and the constant columns; a file without frames is named.

#include "engine/io/particle_frames.hpp"

#include <gtest/gtest.h>

#include "engine/core/input_error.hpp"
#include "engine/io/h5md_reader.hpp"
#include "small_result.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

TEST(ParticleFrames, DescribesTheFramesOfAResultFile) {
  ScratchDirectory scratch("granflow_particle_frames_test_");
  const std::string path = (scratch.path / "result.h5md").string();
  test::write_small_result(path);
  const ParticleFrames frames = ParticleFrames::read(H5mdReader(path), path);
  EXPECT_EQ(frames.frames, 2u);
  EXPECT_EQ(frames.count, 3u);
  EXPECT_EQ(frames.dimension, 3u);
  EXPECT_EQ(frames.times, (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(frames.steps, (std::vector<std::int64_t>{0, 10}));
  EXPECT_EQ(frames.periodic, (std::vector<bool>{true, true, true}));
  EXPECT_TRUE(frames.has_velocity);
  EXPECT_TRUE(frames.has_image);
  EXPECT_EQ(frames.edges(1), (std::vector<double>{2.0, 3.0, 4.0}));
  ASSERT_TRUE(frames.mass && frames.radius && frames.species && frames.id);
  EXPECT_EQ(*frames.mass, (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(*frames.species, (std::vector<std::int64_t>{0, 0, 1}));
}

TEST(ParticleFrames, AFileWithoutFramesIsNamed) {
  ScratchDirectory scratch("granflow_particle_frames_test_");
  const std::string path = (scratch.path / "observables_only.h5md").string();
  {
    H5mdFile file(path, "io_test");
    file.append_observable("x", 0, 0.0, 1.0);
    file.finish();
  }
  try {
    ParticleFrames::read(H5mdReader(path), path);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace granflow
