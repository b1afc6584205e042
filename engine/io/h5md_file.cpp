#include "engine/io/h5md_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "engine/core/units.hpp"
#include "engine/io/file_seal.hpp"
#include "engine/io/h5_write.hpp"
#include "engine/io/provenance.hpp"
#include "engine/io/version.hpp"

namespace granflow {

namespace {

// Chunks of about 64 KiB: a series of scalars keeps 64 frames per chunk, a
// frame of 1000 particles' positions two, larger frames one.
constexpr hsize_t frames_per_chunk = 64;
constexpr hsize_t values_per_chunk = 8192;
constexpr hsize_t values_per_frame_chunk = hsize_t{1} << 20;

void write_string_dataset(hid_t parent, const std::string& name, const std::vector<std::string>& values,
                          bool scalar) {
  std::vector<const char*> pointers;
  for (const auto& v : values) pointers.push_back(v.c_str());
  H5Handle type = string_type();
  write_dataset(parent, name, type, pointers.data(),
                scalar ? std::vector<hsize_t>{} : std::vector<hsize_t>{values.size()});
}

// Short texts as fixed-length strings (each as long as the longest): no
// variable-length data, whose global heap costs milliseconds a dataset.
void write_fixed_strings(hid_t parent, const std::string& name, const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size() + 1);
  std::vector<char> buffer(values.size() * width, '\0');
  for (std::size_t k = 0; k < values.size(); ++k)
    std::copy(values[k].begin(), values[k].end(), buffer.begin() + static_cast<std::ptrdiff_t>(k * width));
  H5Handle type = string_type(width);
  write_dataset(parent, name, type, buffer.data(), {values.size()});
}

H5Handle create_extendible(hid_t parent, const std::string& name, hid_t type, const std::vector<hsize_t>& inner) {
  std::vector<hsize_t> dims{0}, max_dims{H5S_UNLIMITED}, chunk{frames_per_chunk};
  hsize_t inner_count = 1;
  for (hsize_t extent : inner) {
    dims.push_back(extent);
    max_dims.push_back(extent);
    inner_count *= extent;
  }
  chunk[0] = std::clamp<hsize_t>(values_per_chunk / std::max<hsize_t>(inner_count, 1), 1, frames_per_chunk);
  for (hsize_t extent : inner) chunk.push_back(extent);
  // A frame too large for one chunk (HDF5 allows under 4 GiB) is split
  // along its first axis (the particles), so that it is written in blocks.
  if (!inner.empty() && inner_count > values_per_frame_chunk)
    chunk[1] = std::max<hsize_t>(1, values_per_frame_chunk / (inner_count / inner[0]));
  H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), max_dims.data()), H5Sclose,
                 "create extendible space for " + name);
  H5Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "create dataset properties");
  h5_check(H5Pset_chunk(properties, static_cast<int>(chunk.size()), chunk.data()), "set chunking for " + name);
  return H5Handle(H5Dcreate2(parent, name.c_str(), type, space, H5P_DEFAULT, properties, H5P_DEFAULT), H5Dclose,
                  "create dataset " + name);
}

// The block of `count` values from `start` of a dataset, from `data`;
// `writing` says what in an error ("append to X").
void write_block(hid_t dataset, hid_t mem_type, const std::vector<hsize_t>& start, const std::vector<hsize_t>& count,
                 const void* data, const std::string& what, const std::string& writing) {
  H5Handle file_space(H5Dget_space(dataset), H5Sclose, "get space of " + what);
  h5_check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
           "select a block of " + what);
  H5Handle memory_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), H5Sclose,
                        "create memory space");
  h5_check(H5Dwrite(dataset, mem_type, memory_space, file_space, H5P_DEFAULT, data), writing);
}

void append_frame(hid_t dataset, hid_t mem_type, hsize_t frame, const void* data, const std::vector<hsize_t>& inner,
                  const std::string& what) {
  std::vector<hsize_t> dims{frame + 1}, start{frame}, count{1};
  for (hsize_t extent : inner) {
    dims.push_back(extent);
    start.push_back(0);
    count.push_back(extent);
  }
  h5_check(H5Dset_extent(dataset, dims.data()), "extend " + what);
  write_block(dataset, mem_type, start, count, data, what, "append to " + what);
}

// Rows [first, first + rows) of a frame, of `inner` values each.
void write_rows(hid_t dataset, hid_t mem_type, hsize_t frame, hsize_t first, hsize_t rows, const void* data,
                const std::vector<hsize_t>& inner, const std::string& what) {
  std::vector<hsize_t> start{frame, first}, count{1, rows};
  for (std::size_t k = 1; k < inner.size(); ++k) {
    start.push_back(0);
    count.push_back(inner[k]);
  }
  write_block(dataset, mem_type, start, count, data, what, "write rows of " + what);
}

// Reduced units (docs/units.md). MDAnalysis refuses any unit string it does
// not know here, even when asked not to convert units: it reads the frames
// through `granflow export --format mdanalysis`, whose datasets carry none.
std::string particle_unit(const std::string& name) {
  return name == "position" ? unit::length : name == "velocity" ? unit::velocity : "";
}

}  // namespace

struct H5mdFile::Series {
  H5Handle step;
  H5Handle time;
  H5Handle value;
  std::vector<hsize_t> shape;
  hsize_t frames = 0;
  hid_t value_type = H5T_NATIVE_DOUBLE;
  std::string unit, time_unit;
};

// The .partial is claimed with an exclusive lock before HDF5 touches it: a
// second run with the same output stops here instead of truncating the
// first run's file. The lock goes with the process, so a killed run leaves
// no stale claim. HDF5's own locking is off, as this lock replaces it. It is
// an open-file-description lock (fcntl), which the flock() that HDF5 readers
// such as h5py take for reading does not see: the file can be read while it
// is written (flush_if_due).
H5mdFile::H5mdFile(const std::string& path, const std::string& scenario)
    : path_(path), partial_path_(path + ".partial"), started_(std::chrono::steady_clock::now()) {
  h5_quiet();
  lock_ = ::open(partial_path_.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock_ < 0)
    throw InputError(fmt::format("cannot create '{}': {}", partial_path_, std::strerror(errno)));
  struct flock whole_file {};
  whole_file.l_type = F_WRLCK;
  whole_file.l_whence = SEEK_SET;
  if (::fcntl(lock_, F_OFD_SETLK, &whole_file) != 0) {
    ::close(lock_);
    throw InputError(fmt::format("output '{}' is in use by another run ('{}' is locked); wait for it to finish or "
                                 "choose another -o",
                                 path_, partial_path_));
  }
  H5Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "create file access list");
  h5_check(H5Pset_file_locking(access, false, true), "disable HDF5 file locking");
  H5Handle creation(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "create file creation list");
  h5_check(H5Pset_userblock(creation, seal_block_bytes), "reserve the seal block");
  try {
    file_ = H5Handle(H5Fcreate(partial_path_.c_str(), H5F_ACC_TRUNC, creation, access), H5Fclose,
                     "create output file '" + partial_path_ + "'");
  } catch (...) {
    std::filesystem::remove(partial_path_);
    ::close(lock_);
    throw;
  }
  const hid_t h5md = group("/h5md");
  write_numeric_attribute<int>(h5md, "version", H5T_NATIVE_INT, {1, 1});
  const BuildInfo& build = build_info();
  const hid_t creator = group("/h5md/creator");
  write_string_attribute(creator, "name", "granflow");
  write_string_attribute(creator, "version", std::string(build.version) + " (" + build.revision + ")");
  write_string_attribute(group("/h5md/author"), "name", user_name());
  write_string_attribute(group("/parameters"), "scenario", scenario);
  const hid_t provenance = group("/provenance");
  write_string_attribute(provenance, "version", build.version);
  write_string_attribute(provenance, "revision", build.revision);
  write_string_attribute(provenance, "build_type", build.build_type);
  write_string_attribute(provenance, "build_options", build.options);
  write_string_attribute(provenance, "compiler", build.compiler);
  write_string_attribute(provenance, "compiler_flags", build.flags);
  write_string_attribute(provenance, "host", host_name());
  write_string_attribute(provenance, "command_line", recorded_command_line());
  write_numeric_attribute<int>(provenance, "threads", H5T_NATIVE_INT, {thread_limit()});
  write_numeric_attribute<int>(provenance, "ranks", H5T_NATIVE_INT, {rank_count()});
  started_utc_ = utc_timestamp();
  write_string_attribute(provenance, "started_utc", started_utc_);
}

namespace {

const std::vector<std::string> segment_texts{"command_line", "version", "revision", "host", "started_utc", "ended_utc"};

}  // namespace

StateMap H5mdFile::provenance_state() const {
  StateMap segments = earlier_segments_;
  const BuildInfo& build = build_info();
  const std::vector<std::string> current{recorded_command_line(), build.version, build.revision, host_name(),
                                         started_utc_, utc_timestamp()};
  for (std::size_t k = 0; k < segment_texts.size(); ++k) {
    auto& list = segments[segment_texts[k]];
    const auto more = encode_texts({current[k]});
    list.insert(list.end(), more.begin(), more.end());
  }
  segments["threads"].push_back(thread_limit());
  segments["ranks"].push_back(rank_count());
  segments["wall_seconds"].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count());
  return segments;
}

void H5mdFile::restore_provenance(const StateMap& state) {
  const auto threads = state.find("threads");
  if (threads == state.end()) return;  // a checkpoint from before segments were kept
  for (const auto& name : segment_texts) {
    const auto texts = state.find(name);
    if (texts == state.end() || decode_texts(texts->second).size() != threads->second.size())
      throw std::invalid_argument("checkpoint provenance '" + name + "' does not match its segments");
  }
  if (state.count("wall_seconds") == 0 || state.at("wall_seconds").size() != threads->second.size())
    throw std::invalid_argument("checkpoint provenance has no wall times for its segments");
  earlier_segments_ = state;
  // A checkpoint from before ranks were recorded: every segment ran on one.
  if (state.count("ranks") == 0) earlier_segments_["ranks"].assign(threads->second.size(), 1.0);
}

// A file abandoned before finish() (the run threw) is deleted: a .partial
// left behind would only mislead. A killed process leaves it, harmlessly.
H5mdFile::~H5mdFile() {
  if (finished_) return;
  series_.clear();
  groups_.clear();
  file_ = H5Handle();
  std::error_code ignored;
  std::filesystem::remove(partial_path_, ignored);
  ::close(lock_);
}

hid_t H5mdFile::group(const std::string& path) {
  auto it = groups_.find(path);
  if (it != groups_.end()) return it->second;
  const auto slash = path.rfind('/');
  const hid_t parent = slash == 0 ? file_.get() : group(path.substr(0, slash));
  const std::string name = path.substr(slash + 1);
  hid_t id = H5Lexists(parent, name.c_str(), H5P_DEFAULT) > 0 ? H5Gopen2(parent, name.c_str(), H5P_DEFAULT)
                                                                : H5Gcreate2(parent, name.c_str(), H5P_DEFAULT,
                                                                             H5P_DEFAULT, H5P_DEFAULT);
  auto [inserted, ok] = groups_.emplace(path, H5Handle(id, H5Gclose, "open group " + path));
  return inserted->second;
}

void H5mdFile::write_parameters(const Config& config) {
  const hid_t parameters = group("/parameters");
  write_string_dataset(parameters, "toml", {config.to_toml()}, true);
  for (const auto& [key, value] : config.values()) {
    const auto dot = key.rfind('.');
    const hid_t target = dot == std::string::npos ? parameters : group("/parameters/" + key.substr(0, dot));
    const std::string name = dot == std::string::npos ? key : key.substr(dot + 1);
    if (const auto* v = std::get_if<std::int64_t>(&value))
      write_numeric_attribute<std::int64_t>(target, name, H5T_NATIVE_INT64, {*v});
    else if (const auto* d = std::get_if<double>(&value))
      write_numeric_attribute<double>(target, name, H5T_NATIVE_DOUBLE, {*d});
    else if (const auto* b = std::get_if<bool>(&value))
      write_numeric_attribute<int>(target, name, H5T_NATIVE_INT, {*b ? 1 : 0});
    else if (const auto* list = std::get_if<std::vector<double>>(&value); list && !list->empty())
      write_numeric_attribute<double>(target, name, H5T_NATIVE_DOUBLE, *list);
    else if (const auto* text = std::get_if<std::string>(&value))
      write_string_attribute(target, name, *text);
    else
      write_string_attribute(target, name, to_string(value));  // a list of tables, or an empty list, as TOML
  }
}

void H5mdFile::write_box(const std::vector<double>& edges, const std::vector<std::string>& boundary) {
  const hid_t box = group("/particles/all/box");
  write_numeric_attribute<int>(box, "dimension", H5T_NATIVE_INT, {static_cast<int>(edges.size())});
  write_string_array_attribute(box, "boundary", boundary);
  const auto positions = series_.find("/particles/all/position");
  if (positions == series_.end() || positions->second->frames == 0) {
    write_dataset(box, "edges", H5T_NATIVE_DOUBLE, edges.data(), {edges.size()});
    H5Handle dataset(H5Dopen2(box, "edges", H5P_DEFAULT), H5Dclose, "open box/edges");
    write_string_attribute(dataset, "unit", unit::length);
    return;
  }
  const Series& frames = *positions->second;
  const hid_t element = group("/particles/all/box/edges");
  h5_check(H5Lcreate_hard(frames.step, ".", element, "step", H5P_DEFAULT, H5P_DEFAULT), "link box/edges/step");
  h5_check(H5Lcreate_hard(frames.time, ".", element, "time", H5P_DEFAULT, H5P_DEFAULT), "link box/edges/time");
  // Each frame's box as the D x D matrix of its edge vectors (diagonal here),
  // the form of H5MD edges that MDAnalysis reads.
  const std::size_t d = edges.size();
  std::vector<double> matrices(frames.frames * d * d, 0.0);
  for (hsize_t k = 0; k < frames.frames; ++k)
    for (std::size_t a = 0; a < d; ++a) matrices[(k * d + a) * d + a] = edges[a];
  write_dataset(element, "value", H5T_NATIVE_DOUBLE, matrices.data(), {frames.frames, d, d});
  H5Handle dataset(H5Dopen2(element, "value", H5P_DEFAULT), H5Dclose, "open box/edges/value");
  write_string_attribute(dataset, "unit", unit::length);
}

void H5mdFile::write_particle_constant(const std::string& name, const std::vector<double>& data,
                                       std::size_t components, const std::string& unit) {
  const hid_t particles = group("/particles/all");
  std::vector<hsize_t> shape{data.size() / components};
  if (components > 1) shape.push_back(components);
  write_dataset(particles, name, H5T_NATIVE_DOUBLE, data.data(), shape);
  if (!unit.empty()) {
    H5Handle dataset(H5Dopen2(particles, name.c_str(), H5P_DEFAULT), H5Dclose, "open " + name);
    write_string_attribute(dataset, "unit", unit);
  }
}

void H5mdFile::write_particle_constant(const std::string& name, const std::vector<std::int32_t>& data) {
  write_dataset(group("/particles/all"), name, H5T_NATIVE_INT32, data.data(), {data.size()});
}

H5mdFile::Series& H5mdFile::series(const std::string& group_path, std::size_t value_count,
                                   const std::vector<hsize_t>& value_shape, hid_t value_type, const std::string& unit,
                                   const std::string& time_unit) {
  auto it = series_.find(group_path);
  if (it != series_.end()) {
    hsize_t expected = 1;
    for (hsize_t e : it->second->shape) expected *= e;
    if (expected != value_count) throw H5Error("value shape changed between frames of " + group_path);
    return *it->second;
  }
  const hid_t g = group(group_path);
  auto s = std::make_unique<Series>();
  s->shape = value_shape;
  s->value_type = value_type;
  s->unit = unit;
  s->time_unit = time_unit;
  s->step = create_extendible(g, "step", H5T_NATIVE_INT64, {});
  s->time = create_extendible(g, "time", H5T_NATIVE_DOUBLE, {});
  s->value = create_extendible(g, "value", value_type, value_shape);
  if (!unit.empty()) write_string_attribute(s->value, "unit", unit);
  if (!time_unit.empty()) write_string_attribute(s->time, "unit", time_unit);
  return *series_.emplace(group_path, std::move(s)).first->second;
}

void H5mdFile::append_to(Series& s, std::int64_t step, double time, const void* value, const std::string& what) {
  append_frame(s.step, H5T_NATIVE_INT64, s.frames, &step, {}, what + "/step");
  append_frame(s.time, H5T_NATIVE_DOUBLE, s.frames, &time, {}, what + "/time");
  append_frame(s.value, s.value_type, s.frames, value, s.shape, what + "/value");
  ++s.frames;
}

namespace {

// A whole dataset, converted to doubles (exact for the steps and int32 values stored).
std::vector<double> read_all(hid_t dataset, const std::string& what) {
  H5Handle space(H5Dget_space(dataset), H5Sclose, "get space of " + what);
  const hssize_t count = H5Sget_simple_extent_npoints(space);
  if (count < 0) throw H5Error("cannot size " + what);
  std::vector<double> out(static_cast<std::size_t>(count));
  if (count > 0) h5_check(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "read " + what);
  return out;
}

std::vector<double> text_as_numbers(const std::string& text) { return {text.begin(), text.end()}; }
std::string numbers_as_text(const std::vector<double>& numbers) {
  std::string text;
  for (double c : numbers) text.push_back(static_cast<char>(c));
  return text;
}

}  // namespace

StateMap H5mdFile::frames_state(const std::map<std::string, std::size_t>* limit) const {
  StateMap state;
  for (const auto& [path, s] : series_) {
    if (path.rfind("/observables/", 0) == 0) continue;  // the recorder keeps those
    std::size_t frames = s->frames;
    if (limit) {
      const auto cap = limit->find(path);
      if (cap == limit->end()) continue;  // a series begun since
      frames = std::min(frames, cap->second);
    }
    std::size_t inner = 1;
    for (hsize_t e : s->shape) inner *= e;
    auto step = read_all(s->step, path + "/step"), time = read_all(s->time, path + "/time");
    auto value = read_all(s->value, path + "/value");
    step.resize(frames);
    time.resize(frames);
    value.resize(frames * inner);
    state[path + "/step"] = std::move(step);
    state[path + "/time"] = std::move(time);
    state[path + "/value"] = std::move(value);
    state[path + "/shape"].assign(s->shape.begin(), s->shape.end());
    state[path + "/integer"] = {s->value_type == H5T_NATIVE_INT32 ? 1.0 : 0.0};
    state[path + "/unit"] = text_as_numbers(s->unit);
    state[path + "/time_unit"] = text_as_numbers(s->time_unit);
  }
  return state;
}

std::map<std::string, std::size_t> H5mdFile::frame_counts() const {
  std::map<std::string, std::size_t> counts;
  for (const auto& [path, s] : series_) counts[path] = s->frames;
  return counts;
}

std::size_t H5mdFile::particles_in_frames(const std::string& name) const {
  const auto s = series_.find("/particles/all/" + name);
  return s == series_.end() || s->second->shape.empty() ? 0 : static_cast<std::size_t>(s->second->shape.front());
}

void H5mdFile::restore_frames(const StateMap& state, const std::map<std::string, std::size_t>* limit) {
  const std::string suffix = "/shape";
  for (const auto& [key, shape_values] : state) {
    if (key.size() <= suffix.size() || key.compare(key.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
    const std::string path = key.substr(0, key.size() - suffix.size());
    std::size_t frames = state.at(path + "/step").size();
    if (limit) {
      const auto cap = limit->find(path);
      if (cap == limit->end()) continue;
      frames = std::min(frames, cap->second);
    }
    const auto& step = state.at(path + "/step");
    const auto& time = state.at(path + "/time");
    const auto& value = state.at(path + "/value");
    const bool integer = state.at(path + "/integer").at(0) != 0.0;
    const std::vector<hsize_t> shape(shape_values.begin(), shape_values.end());
    std::size_t inner = 1;
    for (hsize_t e : shape) inner *= e;
    if (step.size() != time.size() || value.size() != step.size() * inner)
      throw std::invalid_argument("checkpoint frames of " + path + " have inconsistent sizes");
    for (std::size_t f = 0; f < frames; ++f) {
      Series& s = series(path, inner, shape, integer ? H5T_NATIVE_INT32 : H5T_NATIVE_DOUBLE,
                         numbers_as_text(state.at(path + "/unit")), numbers_as_text(state.at(path + "/time_unit")));
      const double* frame = value.data() + f * inner;
      if (integer) {
        const std::vector<std::int32_t> ints(frame, frame + inner);
        append_to(s, static_cast<std::int64_t>(step[f]), time[f], ints.data(), path);
      } else {
        append_to(s, static_cast<std::int64_t>(step[f]), time[f], frame, path);
      }
    }
  }
}

void H5mdFile::append_particle_frame(const std::string& name, std::int64_t step, double time,
                                     const std::vector<double>& data, std::size_t components) {
  std::vector<hsize_t> shape{data.size() / components};
  if (components > 1) shape.push_back(components);
  append_to(series("/particles/all/" + name, data.size(), shape, H5T_NATIVE_DOUBLE, particle_unit(name), unit::time),
            step, time, data.data(), name);
}

void H5mdFile::begin_particle_frame(const std::string& name, std::int64_t step, double time, std::size_t count,
                                    std::size_t components, bool integers) {
  std::vector<hsize_t> shape{count};
  if (components > 1) shape.push_back(components);
  Series& s = series("/particles/all/" + name, count * components, shape,
                     integers ? H5T_NATIVE_INT32 : H5T_NATIVE_DOUBLE, integers ? "" : particle_unit(name), unit::time);
  append_frame(s.step, H5T_NATIVE_INT64, s.frames, &step, {}, name + "/step");
  append_frame(s.time, H5T_NATIVE_DOUBLE, s.frames, &time, {}, name + "/time");
  std::vector<hsize_t> dims{s.frames + 1};
  dims.insert(dims.end(), s.shape.begin(), s.shape.end());
  h5_check(H5Dset_extent(s.value, dims.data()), "extend " + name + "/value");
  ++s.frames;
}

void H5mdFile::write_particle_rows(const std::string& name, std::size_t first, std::size_t rows, const double* data) {
  Series& s = *series_.at("/particles/all/" + name);
  write_rows(s.value, H5T_NATIVE_DOUBLE, s.frames - 1, first, rows, data, s.shape, name + "/value");
}

void H5mdFile::write_particle_rows(const std::string& name, std::size_t first, std::size_t rows,
                                   const std::int32_t* data) {
  Series& s = *series_.at("/particles/all/" + name);
  write_rows(s.value, H5T_NATIVE_INT32, s.frames - 1, first, rows, data, s.shape, name + "/value");
}

void H5mdFile::append_particle_frame(const std::string& name, std::int64_t step, double time,
                                     const std::vector<std::int32_t>& data, std::size_t components) {
  std::vector<hsize_t> shape{data.size() / components};
  if (components > 1) shape.push_back(components);
  append_to(series("/particles/all/" + name, data.size(), shape, H5T_NATIVE_INT32, "", unit::time), step, time,
            data.data(), name);
}

void H5mdFile::append_observable(const std::string& name, std::int64_t step, double time, double value) {
  append_observable_frame(name, step, time, &value, 1, {});
}

void H5mdFile::append_observable(const std::string& name, std::int64_t step, double time,
                                 const std::vector<double>& value) {
  append_observable_frame(name, step, time, value.data(), value.size(), {value.size()});
}

void H5mdFile::append_observable_frame(const std::string& name, std::int64_t step, double time, const double* value,
                                       std::size_t count, const std::vector<hsize_t>& shape) {
  const auto unit = units_.find(name);
  append_to(series("/observables/" + name, count, shape, H5T_NATIVE_DOUBLE, unit == units_.end() ? "" : unit->second,
                   unit::time),
            step, time, value, name);
}

void H5mdFile::append_field(const std::string& name, std::int64_t step, double time,
                            const std::vector<double>& values, const std::vector<hsize_t>& shape,
                            const std::string& unit) {
  append_to(series("/fields/" + name, values.size(), shape, H5T_NATIVE_DOUBLE, unit, unit::time), step, time,
            values.data(), name);
}

void H5mdFile::write_result(const std::string& name, const std::vector<double>& value, const std::string& unit) {
  const hid_t results = group("/results");
  write_dataset(results, name, H5T_NATIVE_DOUBLE, value.data(), {value.size()});
  H5Handle dataset(H5Dopen2(results, name.c_str(), H5P_DEFAULT), H5Dclose, "open " + name);
  write_string_attribute(dataset, "unit", unit);
}

void H5mdFile::write_profile(const std::vector<ProfileEntry>& entries) {
  const hid_t profile = group("/profile");
  std::vector<std::string> names;
  std::vector<std::uint64_t> calls;
  std::vector<double> total, mean;
  for (const auto& e : entries) {
    names.push_back(e.system);
    calls.push_back(e.calls);
    total.push_back(e.total_seconds);
    mean.push_back(e.mean_seconds());
  }
  const std::vector<hsize_t> shape{entries.size()};
  write_string_dataset(profile, "system", names, false);
  write_dataset(profile, "calls", H5T_NATIVE_UINT64, calls.data(), shape);
  write_dataset(profile, "total_seconds", H5T_NATIVE_DOUBLE, total.data(), shape);
  write_dataset(profile, "mean_seconds", H5T_NATIVE_DOUBLE, mean.data(), shape);
}

void H5mdFile::write_array(const std::string& group_path, const std::string& name, const std::vector<double>& values) {
  write_dataset(group(group_path), name, H5T_NATIVE_DOUBLE, values.data(), {values.size()});
}

void H5mdFile::create_array(const std::string& group_path, const std::string& name, std::size_t count) {
  const hsize_t size = count;
  H5Handle space(H5Screate_simple(1, &size, nullptr), H5Sclose, "create space for " + name);
  const H5Handle dataset(
      H5Dcreate2(group(group_path), name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose, "create dataset " + name);
}

void H5mdFile::write_array_block(const std::string& group_path, const std::string& name, std::size_t first,
                                 const std::vector<double>& values) {
  if (values.empty()) return;
  H5Handle dataset(H5Dopen2(group(group_path), name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + name);
  write_block(dataset, H5T_NATIVE_DOUBLE, {first}, {values.size()}, values.data(), name, "write to " + name);
}

void H5mdFile::write_text_array(const std::string& group_path, const std::string& name,
                                const std::vector<std::string>& values) {
  write_string_dataset(group(group_path), name, values, false);
}

void H5mdFile::write_attribute(const std::string& path, const std::string& name, const std::string& value) {
  write_string_attribute(group(path), name, value);
}

void H5mdFile::write_attribute(const std::string& path, const std::string& name, double value) {
  write_numeric_attribute<double>(group(path), name, H5T_NATIVE_DOUBLE, {value});
}


void H5mdFile::flush_if_due() {
  if (std::chrono::steady_clock::now() - last_flush_ >= std::chrono::seconds(1)) flush();
}

void H5mdFile::flush() {
  h5_check(H5Fflush(file_, H5F_SCOPE_LOCAL), "flush '" + partial_path_ + "'");
  last_flush_ = std::chrono::steady_clock::now();
}

void H5mdFile::finish() {
  if (finished_) return;
  const hid_t provenance = group("/provenance");
  const StateMap segments = provenance_state();
  const hid_t listed = group("/provenance/segments");
  for (const auto& name : segment_texts) write_fixed_strings(listed, name, decode_texts(segments.at(name)));
  for (const auto* name : {"threads", "ranks", "wall_seconds"})
    write_dataset(listed, name, H5T_NATIVE_DOUBLE, segments.at(name).data(), {segments.at(name).size()});
  write_string_attribute(provenance, "finished_utc", utc_timestamp());
  write_numeric_attribute<double>(
      provenance, "wall_seconds", H5T_NATIVE_DOUBLE,
      {std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count()});
  series_.clear();
  groups_.clear();
  file_.close("close output file '" + partial_path_ + "'");
  seal_file(partial_path_);
  std::error_code error;
  std::filesystem::rename(partial_path_, path_, error);
  if (error) throw H5Error("cannot move '" + partial_path_ + "' to '" + path_ + "': " + error.message());
  finished_ = true;
  ::close(lock_);
}

}  // namespace granflow
