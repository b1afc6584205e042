#include "engine/io/particle_frames.hpp"

#include <fmt/format.h>

#include "engine/core/input_error.hpp"

namespace granflow {

std::vector<double> ParticleFrames::edges(std::size_t frame) const {
  return frame_edges_.empty() ? fixed_edges_ : frame_edges_.at(frame);
}

ParticleFrames ParticleFrames::read(const H5mdReader& reader, const std::string& path) {
  const std::string& p = particles_group;
  if (!reader.exists(p + "/position/value"))
    throw InputError(fmt::format("'{}' has no particle frames ({}/position): run with output.positions = \"all\", "
                                 "\"first_last\" or \"final\"",
                                 path, p));
  ParticleFrames f;
  const auto shape = reader.shape(p + "/position/value");
  if (shape.size() == 2 || (shape.size() == 3 && shape[2] == 1))
    throw InputError(fmt::format("'{}' holds the frames of a 1D run: the exports and stored starts take 2D and 3D "
                                 "runs only (read 1D frames with h5py, {}/position/value)",
                                 path, p));
  if (shape.size() != 3 || shape[2] < 2 || shape[2] > 3)
    throw InputError(fmt::format("'{}': positions are not frames x N x 2 or frames x N x 3", path));
  f.frames = shape[0];
  f.count = shape[1];
  f.dimension = shape[2];
  f.times = reader.doubles(p + "/position/time").values;
  f.steps = reader.integers(p + "/position/step");
  f.has_velocity = reader.exists(p + "/velocity/value");
  f.has_image = reader.exists(p + "/image/value");
  if (reader.exists(p + "/box/edges/value")) {
    const auto matrices = reader.doubles(p + "/box/edges/value").values;
    const std::size_t d = f.dimension;
    for (std::size_t k = 0; k < f.frames; ++k) {
      std::vector<double> edges(d);
      for (std::size_t a = 0; a < d; ++a) edges[a] = matrices[(k * d + a) * d + a];
      f.frame_edges_.push_back(std::move(edges));
    }
  } else if (reader.exists(p + "/box/edges")) {
    f.fixed_edges_ = reader.doubles(p + "/box/edges").values;
  }
  f.periodic.assign(f.dimension, true);
  if (reader.exists(p + "/box")) {
    const auto boundary = reader.string_list_attribute(p + "/box", "boundary");
    for (std::size_t a = 0; a < f.dimension && a < boundary.size(); ++a) f.periodic[a] = boundary[a] == "periodic";
  }
  if (reader.exists(p + "/radius")) f.radius = reader.doubles(p + "/radius").values;
  if (reader.exists(p + "/mass")) f.mass = reader.doubles(p + "/mass").values;
  if (reader.exists(p + "/species")) f.species = reader.integers(p + "/species");
  if (reader.exists(p + "/id")) f.id = reader.integers(p + "/id");
  return f;
}

}  // namespace granflow
