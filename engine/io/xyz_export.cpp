#include "engine/io/xyz_export.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "engine/core/input_error.hpp"
#include "engine/io/particle_frames.hpp"

namespace granflow {

namespace {

constexpr std::array<const char*, 36> element_symbols{
    "H",  "He", "Li", "Be", "B",  "C",  "N",  "O",  "F",  "Ne", "Na", "Mg", "Al", "Si", "P",  "S",  "Cl", "Ar",
    "K",  "Ca", "Sc", "Ti", "V",  "Cr", "Mn", "Fe", "Co", "Ni", "Cu", "Zn", "Ga", "Ge", "As", "Se", "Br", "Kr"};

}  // namespace

std::size_t export_extended_xyz(const std::string& result, const std::string& output) {
  const H5mdReader reader(result);
  const auto frames = ParticleFrames::read(reader, result);
  const std::size_t n = frames.count, d = frames.dimension;
  std::vector<std::int64_t> species(n, 0);
  if (frames.species) species = *frames.species;
  for (std::int64_t s : species)
    if (s < 0 || s >= static_cast<std::int64_t>(element_symbols.size()))
      throw InputError(fmt::format("'{}': species {} has no chemical symbol to stand for it in extended XYZ "
                                   "(0 to {} do)",
                                   result, s, element_symbols.size() - 1));
  std::string pbc;
  for (std::size_t a = 0; a < 3; ++a) pbc += std::string(a ? " " : "") + (a < d && frames.periodic[a] ? "T" : "F");
  std::string properties = "species:S:1:pos:R:3";
  if (frames.has_velocity) properties += ":velo:R:3";
  if (frames.has_velocity && frames.mass) properties += ":momenta:R:3";
  if (frames.mass) properties += ":masses:R:1";
  if (frames.radius) properties += ":radius:R:1";
  if (frames.has_image) properties += ":image:I:3";
  properties += ":typeid:I:1:id:I:1";

  const std::string partial = output + ".partial";
  std::FILE* out = std::fopen(partial.c_str(), "w");
  if (!out) throw InputError(fmt::format("cannot write '{}'", partial));
  const std::string& p = particles_group;
  for (std::size_t f = 0; f < frames.frames; ++f) {
    const auto position = reader.frame(p + "/position/value", f).values;
    const auto velocity = frames.has_velocity ? reader.frame(p + "/velocity/value", f).values : std::vector<double>{};
    const auto image = frames.has_image ? reader.frame(p + "/image/value", f).values : std::vector<double>{};
    const auto edges = frames.edges(f);
    const auto edge = [&](std::size_t a) { return a < edges.size() ? edges[a] : 1.0; };
    fmt::print(out, "{}\nLattice=\"{:.17g} 0 0 0 {:.17g} 0 0 0 {:.17g}\" Properties={} Time={:.17g} Step={} pbc=\"{}\"\n",
               n, edge(0), edge(1), d == 3 ? edge(2) : 1.0, properties, frames.times[f], frames.steps[f], pbc);
    for (std::size_t i = 0; i < n; ++i) {
      const auto column = [&](const std::vector<double>& data, std::size_t a) { return a < d ? data[i * d + a] : 0.0; };
      fmt::print(out, "{}", element_symbols[static_cast<std::size_t>(species[i])]);
      for (std::size_t a = 0; a < 3; ++a) fmt::print(out, " {:.10g}", column(position, a));
      if (frames.has_velocity)
        for (std::size_t a = 0; a < 3; ++a) fmt::print(out, " {:.10g}", column(velocity, a));
      if (frames.has_velocity && frames.mass)
        for (std::size_t a = 0; a < 3; ++a) fmt::print(out, " {:.10g}", (*frames.mass)[i] * column(velocity, a));
      if (frames.mass) fmt::print(out, " {:.10g}", (*frames.mass)[i]);
      if (frames.radius) fmt::print(out, " {:.10g}", (*frames.radius)[i]);
      if (frames.has_image)
        for (std::size_t a = 0; a < 3; ++a) fmt::print(out, " {}", static_cast<std::int64_t>(column(image, a)));
      fmt::print(out, " {} {}\n", species[i], frames.id ? (*frames.id)[i] : static_cast<std::int64_t>(i));
    }
  }
  const bool written = std::fflush(out) == 0 && !std::ferror(out);
  std::fclose(out);
  if (!written) {
    std::filesystem::remove(partial);
    throw InputError(fmt::format("cannot write '{}' (disk full?)", partial));
  }
  std::filesystem::rename(partial, output);
  return frames.frames;
}

}  // namespace granflow
