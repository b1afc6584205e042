#include "engine/io/mdanalysis_export.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <vector>

#include "engine/core/input_error.hpp"
#include "engine/io/h5_write.hpp"
#include "engine/io/h5md_reader.hpp"
#include "engine/io/particle_frames.hpp"

namespace granflow {

namespace {

// The rows of a series at the frames' steps, or nothing where a frame's step
// is not in it.
std::optional<std::vector<std::size_t>> rows_at(const std::vector<std::int64_t>& series_steps,
                                                const std::vector<std::int64_t>& frame_steps) {
  std::map<std::int64_t, std::size_t> row_of;
  for (std::size_t k = 0; k < series_steps.size(); ++k) row_of.emplace(series_steps[k], k);
  std::vector<std::size_t> rows;
  for (std::int64_t step : frame_steps) {
    const auto it = row_of.find(step);
    if (it == row_of.end()) return std::nullopt;
    rows.push_back(it->second);
  }
  return rows;
}

void copy_unit(const H5mdReader& reader, const std::string& from, hid_t to) {
  if (reader.exists(from)) {
    const auto names = reader.attribute_names(from);
    if (std::find(names.begin(), names.end(), "unit") != names.end())
      write_string_attribute(to, "unit", reader.string_attribute(from, "unit"));
  }
}

H5Handle open_dataset(hid_t parent, const std::string& name) {
  return H5Handle(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), H5Dclose, "open " + name);
}

H5Handle create_group(hid_t parent, const std::string& name) {
  return H5Handle(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                  "create group " + name);
}

// Series `name` at the frames' rows, as /observables/NAME/{step,time,value}.
void write_series_at_frames(const H5mdReader& reader, const std::string& name, const std::vector<std::size_t>& rows,
                            hid_t observables) {
  const std::string source = "/observables/" + name;
  const auto steps = reader.integers(source + "/step");
  const auto times = reader.doubles(source + "/time").values;
  const DoubleArray values = reader.doubles(source + "/value");
  const std::size_t width = values.shape.empty() || values.shape[0] == 0 ? 1 : values.values.size() / values.shape[0];
  std::vector<std::int64_t> step;
  std::vector<double> time, value;
  for (std::size_t row : rows) {
    step.push_back(steps[row]);
    time.push_back(times[row]);
    value.insert(value.end(), values.values.begin() + static_cast<std::ptrdiff_t>(row * width),
                 values.values.begin() + static_cast<std::ptrdiff_t>((row + 1) * width));
  }
  std::vector<hsize_t> shape{rows.size()};
  for (std::size_t a = 1; a < values.shape.size(); ++a) shape.push_back(values.shape[a]);
  const H5Handle series = create_group(observables, name);
  write_dataset(series, "step", H5T_NATIVE_INT64, step.data(), {rows.size()});
  write_dataset(series, "time", H5T_NATIVE_DOUBLE, time.data(), {rows.size()});
  write_dataset(series, "value", H5T_NATIVE_DOUBLE, value.data(), shape);
  copy_unit(reader, source + "/time", open_dataset(series, "time"));
  copy_unit(reader, source + "/value", open_dataset(series, "value"));
}

// /particles/trajectory: the frames' positions and velocities mapped onto
// the result file, their steps and times, and the box, all without units
// (MDAnalysis refuses reduced ones).
void write_trajectory(const H5mdReader& reader, const ParticleFrames& frames, const std::string& source,
                      hid_t particles) {
  const H5Handle trajectory = create_group(particles, "trajectory");
  const hsize_t count = frames.frames;
  for (const char* element : {"position", "velocity"}) {
    const std::string from = particles_group + "/" + element + "/value";
    if (!reader.exists(from)) continue;
    const H5Handle group = create_group(trajectory, element);
    write_dataset(group, "step", H5T_NATIVE_INT64, frames.steps.data(), {count});
    write_dataset(group, "time", H5T_NATIVE_DOUBLE, frames.times.data(), {count});
    const auto shape = reader.shape(from);
    const H5Handle whole = simple_space({shape.begin(), shape.end()}, from);
    write_virtual_dataset(group, "value", H5T_NATIVE_DOUBLE, {shape.begin(), shape.end()}, whole, source, from, whole);
  }
  const H5Handle box = create_group(trajectory, "box");
  write_numeric_attribute<int>(box, "dimension", H5T_NATIVE_INT, {static_cast<int>(frames.dimension)});
  write_string_array_attribute(box, "boundary", reader.string_list_attribute(particles_group + "/box", "boundary"));
  // Each frame's box as the D x D matrix of its edges, the form MDAnalysis reads.
  const H5Handle edges = create_group(box, "edges");
  write_dataset(edges, "step", H5T_NATIVE_INT64, frames.steps.data(), {count});
  write_dataset(edges, "time", H5T_NATIVE_DOUBLE, frames.times.data(), {count});
  const std::size_t d = frames.dimension;
  std::vector<double> matrices(count * d * d, 0.0);
  for (std::size_t f = 0; f < count; ++f) {
    const auto frame_edges = frames.edges(f);
    for (std::size_t a = 0; a < d; ++a) matrices[(f * d + a) * d + a] = frame_edges[a];
  }
  write_dataset(edges, "value", H5T_NATIVE_DOUBLE, matrices.data(), {count, d, d});
}

void write_view(const H5mdReader& reader, const ParticleFrames& frames, const std::string& result,
                const std::string& output, const std::string& partial) {
  H5Handle file(H5Fcreate(partial.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create " + partial);
  const std::string source = std::filesystem::relative(std::filesystem::absolute(result),
                                                       std::filesystem::absolute(output).parent_path())
                                 .string();
  h5_check(H5Lcreate_external(source.c_str(), "/h5md", file, "h5md", H5P_DEFAULT, H5P_DEFAULT), "link /h5md");
  {
    const H5Handle particles = create_group(file, "particles");
    write_trajectory(reader, frames, source, particles);
    const H5Handle observables = create_group(file, "observables");
    std::vector<std::string> kept, left_out;
    if (reader.exists("/observables"))
      for (const auto& name : reader.members("/observables")) {
        const std::string series = "/observables/" + name;
        if (!reader.exists(series + "/step") || !reader.exists(series + "/value")) continue;
        if (const auto rows = rows_at(reader.integers(series + "/step"), frames.steps)) {
          write_series_at_frames(reader, name, *rows, observables);
          kept.push_back(name);
        } else {
          left_out.push_back(name);
        }
      }
    spdlog::info("series at every frame, in MDAnalysis's ts.data: {}",
                 kept.empty() ? std::string("none") : fmt::format("{}", fmt::join(kept, ", ")));
    if (!left_out.empty())
      spdlog::info("series not sampled at every frame, left out (read them by time from '{}'): {}", result,
                   fmt::join(left_out, ", "));
  }
  file.close("close " + partial);
}

}  // namespace

std::size_t export_mdanalysis(const std::string& result, const std::string& output) {
  const H5mdReader reader(result);
  const ParticleFrames frames = ParticleFrames::read(reader, result);
  if (frames.dimension != 3)
    throw InputError(fmt::format("'{}' is {}D: MDAnalysis reads 3D boxes only; export it with --format gsd, which "
                                 "MDAnalysis reads as HOOMD writes {}D systems",
                                 result, frames.dimension, frames.dimension));
  const std::string partial = output + ".partial";
  try {
    write_view(reader, frames, result, output, partial);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    throw;
  }
  std::filesystem::rename(partial, output);
  return frames.frames;
}

}  // namespace granflow
