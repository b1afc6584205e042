#pragma once
// The particle frames of a result file (/particles/all) as the exporters read
// them: how many, of how many particles in how many dimensions, the box of
// each frame and which axes are periodic, and the time-independent columns.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/io/h5md_reader.hpp"

namespace granflow {

inline const std::string particles_group = "/particles/all";

struct ParticleFrames {
  std::size_t frames = 0;
  std::size_t count = 0;
  std::size_t dimension = 0;
  std::vector<double> times;
  std::vector<std::int64_t> steps;
  std::vector<bool> periodic;  // per axis
  bool has_velocity = false;
  bool has_image = false;
  std::optional<std::vector<double>> radius, mass;
  std::optional<std::vector<std::int64_t>> species, id;

  // The box edges of frame f (the box may change between frames).
  std::vector<double> edges(std::size_t frame) const;

  // Throws InputError naming the file where it has no particle frames.
  static ParticleFrames read(const H5mdReader& reader, const std::string& path);

 private:
  std::vector<double> fixed_edges_;
  std::vector<std::vector<double>> frame_edges_;
};

}  // namespace granflow
