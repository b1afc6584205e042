#include "engine/io/stored_state.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "engine/core/input_error.hpp"
#include "engine/io/gsd_layout.hpp"
#include "engine/io/h5_handle.hpp"
#include "engine/io/h5md_reader.hpp"
#include "engine/io/particle_frames.hpp"

namespace granflow {

namespace {

std::size_t frame_index(const std::string& path, std::int64_t frame, std::size_t frames) {
  if (frames == 0) throw InputError(fmt::format("initial.from = '{}' holds no frames", path));
  const auto n = static_cast<std::int64_t>(frames);
  const std::int64_t index = frame < 0 ? n + frame : frame;
  if (index < 0 || index >= n)
    throw InputError(fmt::format("initial.frame = {}: '{}' holds {} frames (0 to {}, or -1 to -{} from the end)", frame,
                                 path, frames, frames - 1, frames));
  return static_cast<std::size_t>(index);
}

// A result file's frame `frame`; with `particles` false, all but the
// positions and velocities (`has_velocity` says whether it has the latter).
StoredState read_h5md(const std::string& path, std::int64_t frame, bool particles = true,
                      std::size_t* index = nullptr, bool* has_velocity = nullptr) {
  try {
    const H5mdReader reader(path);
    const auto frames = ParticleFrames::read(reader, path);
    const std::size_t f = frame_index(path, frame, frames.frames);
    StoredState s;
    s.source = fmt::format("'{}', frame {} of {} (t = {:.6g})", path, f, frames.frames, frames.times[f]);
    s.dimension = frames.dimension;
    s.count = frames.count;
    s.edges = frames.edges(f);
    s.periodic = frames.periodic;
    if (particles) {
      s.position = reader.frame(particles_group + "/position/value", f).values;
      if (frames.has_velocity) s.velocity = reader.frame(particles_group + "/velocity/value", f).values;
    }
    if (frames.radius) s.radius = *frames.radius;
    if (frames.mass) s.mass = *frames.mass;
    if (frames.species) s.species = *frames.species;
    if (index) *index = f;
    if (has_velocity) *has_velocity = frames.has_velocity;
    return s;
  } catch (const H5Error& error) {
    throw InputError(fmt::format("initial.from = '{}': cannot read it as a granflow result file: {}", path,
                                 error.what()));
  }
}

// The GSD file layer (version 1 or 2) and the HOOMD schema's chunks.
class GsdFile {
 public:
  explicit GsdFile(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    GsdHeader header;
    read_at(0, &header, sizeof header);
    if (header.gsd_version >= gsd_version(3, 0) || header.gsd_version < gsd_version(1, 0))
      fail(fmt::format("GSD file version {}.{} is not one this reader knows (1.x, 2.x)", header.gsd_version >> 16,
                       header.gsd_version & 0xffff));
    const bool version1 = header.gsd_version < gsd_version(2, 0);
    if (header.namelist_allocated_entries > (1u << 24)) fail("its name list is implausibly large");
    std::vector<char> names(header.namelist_allocated_entries * 64);
    read_at(header.namelist_location, names.data(), names.size());
    for (std::size_t at = 0; at < names.size() && names[at] != 0;) {
      const std::string name(&names[at], strnlen(&names[at], names.size() - at));
      ids_[name] = static_cast<std::uint16_t>(name_count_++);
      at += version1 ? 64 : name.size() + 1;
    }
    if (header.index_allocated_entries > (1ull << 32)) fail("its index is implausibly large");
    index_.resize(header.index_allocated_entries);
    read_at(header.index_location, index_.data(), index_.size() * sizeof(GsdIndexEntry));
    while (!index_.empty() && index_.back().location == 0) index_.pop_back();
    frames_ = index_.empty() ? 0 : index_.back().frame + 1;
  }

  std::size_t frames() const { return frames_; }

  // The chunk of frame f, or of frame 0 where f has none (the HOOMD schema's
  // rule), as doubles; empty where neither has it.
  std::vector<double> chunk(const std::string& name, std::size_t f, std::size_t* columns = nullptr) {
    const auto id = ids_.find(name);
    if (id == ids_.end()) return {};
    const GsdIndexEntry* found = nullptr;
    for (const auto& e : index_)
      if (e.name == id->second && (e.frame == f || (e.frame == 0 && !found))) found = &e;
    if (!found) return {};
    if (columns) *columns = found->columns;
    const std::size_t count = found->rows * found->columns;
    if (count > (1ull << 34)) fail(fmt::format("chunk {} is implausibly large", name));
    const std::size_t size = gsd_type_size(found->type);
    if (size == 0) fail(fmt::format("chunk {} has a type ({}) this reader does not know", name, found->type));
    std::vector<char> bytes(count * size);
    read_at(static_cast<std::uint64_t>(found->location), bytes.data(), bytes.size());
    std::vector<double> out(count);
    for (std::size_t k = 0; k < count; ++k) out[k] = element(bytes.data() + k * size, found->type);
    return out;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("initial.from = '{}': {}", path_, what));
  }

 private:
  static double element(const char* p, std::uint8_t type) {
    const auto get = [p](auto value) {
      std::memcpy(&value, p, sizeof value);
      return static_cast<double>(value);
    };
    switch (static_cast<GsdType>(type)) {
      case GsdType::uint8: return get(std::uint8_t{});
      case GsdType::uint16: return get(std::uint16_t{});
      case GsdType::uint32: return get(std::uint32_t{});
      case GsdType::uint64: return get(std::uint64_t{});
      case GsdType::int8: return get(std::int8_t{});
      case GsdType::int16: return get(std::int16_t{});
      case GsdType::int32: return get(std::int32_t{});
      case GsdType::int64: return get(std::int64_t{});
      case GsdType::float32: return get(float{});
      default: return get(double{});
    }
  }

  void read_at(std::uint64_t offset, void* to, std::size_t bytes) {
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(static_cast<char*>(to), static_cast<std::streamsize>(bytes));
    if (!in_ || in_.gcount() != static_cast<std::streamsize>(bytes)) fail("it is truncated or not a GSD file");
  }

  std::string path_;
  std::ifstream in_;
  std::map<std::string, std::uint16_t> ids_;
  std::size_t name_count_ = 0;
  std::vector<GsdIndexEntry> index_;
  std::size_t frames_ = 0;
};

StoredState read_gsd(const std::string& path, std::int64_t frame) {
  GsdFile gsd(path);
  const std::size_t f = frame_index(path, frame, gsd.frames());
  StoredState s;
  s.source = fmt::format("'{}', frame {} of {}", path, f, gsd.frames());
  const auto dimensions = gsd.chunk("configuration/dimensions", f);
  s.dimension = dimensions.empty() ? 3 : static_cast<std::size_t>(dimensions[0]);
  if (s.dimension != 2 && s.dimension != 3) gsd.fail(fmt::format("configuration/dimensions is {}", s.dimension));
  auto box = gsd.chunk("configuration/box", f);
  if (box.empty()) box = {1, 1, 1, 0, 0, 0};
  if (box.size() != 6) gsd.fail("configuration/box does not hold 6 numbers");
  if (box[3] != 0 || box[4] != 0 || box[5] != 0)
    gsd.fail(fmt::format("the box is tilted (xy, xz, yz = {}, {}, {}); granflow's boxes are rectangular", box[3],
                         box[4], box[5]));
  s.edges.assign(box.begin(), box.begin() + static_cast<std::ptrdiff_t>(s.dimension));
  s.periodic.assign(s.dimension, true);  // HOOMD's boxes are periodic
  const auto n = gsd.chunk("particles/N", f);
  s.count = n.empty() ? 0 : static_cast<std::size_t>(n[0]);
  std::size_t columns = 0;
  const auto position = gsd.chunk("particles/position", f, &columns);
  if (position.size() != s.count * 3 || columns != 3)
    gsd.fail(fmt::format("particles/position holds {} numbers, not N x 3 = {}", position.size(), s.count * 3));
  const auto column_of = [&](const std::string& name, std::size_t width, double fallback) {
    auto values = gsd.chunk(name, f);
    if (values.empty()) values.assign(s.count * width, fallback);
    if (values.size() != s.count * width)
      gsd.fail(fmt::format("{} holds {} numbers, not {}", name, values.size(), s.count * width));
    return values;
  };
  const auto velocity = column_of("particles/velocity", 3, 0.0);
  const auto diameter = column_of("particles/diameter", 1, 1.0);
  s.mass = column_of("particles/mass", 1, 1.0);
  const auto typeid_ = column_of("particles/typeid", 1, 0.0);
  for (std::size_t i = 0; i < s.count; ++i) {
    for (std::size_t a = 0; a < s.dimension; ++a) {
      s.position.push_back(position[i * 3 + a] + 0.5 * s.edges[a]);
      s.velocity.push_back(velocity[i * 3 + a]);
    }
    s.radius.push_back(0.5 * diameter[i]);
    s.species.push_back(static_cast<std::int64_t>(typeid_[i]));
  }
  return s;
}

// key=value pairs of an extended XYZ comment line; values may be quoted.
std::map<std::string, std::string> comment_pairs(const std::string& line) {
  std::map<std::string, std::string> pairs;
  std::size_t at = 0;
  while (at < line.size()) {
    while (at < line.size() && std::isspace(static_cast<unsigned char>(line[at]))) ++at;
    const std::size_t key_start = at;
    while (at < line.size() && line[at] != '=' && !std::isspace(static_cast<unsigned char>(line[at]))) ++at;
    std::string key = line.substr(key_start, at - key_start), value = "T";
    if (at < line.size() && line[at] == '=') {
      ++at;
      if (at < line.size() && (line[at] == '"' || line[at] == '\'' || line[at] == '{' || line[at] == '[')) {
        const char close = line[at] == '{' ? '}' : line[at] == '[' ? ']' : line[at];
        const std::size_t end = line.find(close, at + 1);
        value = line.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1);
        at = end == std::string::npos ? line.size() : end + 1;
      } else {
        const std::size_t start = at;
        while (at < line.size() && !std::isspace(static_cast<unsigned char>(line[at]))) ++at;
        value = line.substr(start, at - start);
      }
    }
    if (!key.empty()) pairs[key] = value;
  }
  return pairs;
}

StoredState read_xyz(const std::string& path, std::int64_t frame) {
  std::ifstream in(path);
  std::vector<std::streampos> starts;
  std::vector<std::size_t> counts;
  std::string line;
  const auto fail = [&](const std::string& what) -> void {
    throw InputError(fmt::format("initial.from = '{}' (read as extended XYZ): {}", path, what));
  };
  while (true) {
    const std::streampos at = in.tellg();
    if (!std::getline(in, line)) break;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::size_t n = 0;
    try {
      std::size_t used = 0;
      n = std::stoul(line, &used);
      if (line.find_first_not_of(" \t\r", used) != std::string::npos) throw std::invalid_argument("");
    } catch (const std::exception&) {
      fail(fmt::format("expected a particle count at the start of frame {}, found '{}'", starts.size(), line.substr(0, 40)));
    }
    starts.push_back(at);
    counts.push_back(n);
    for (std::size_t k = 0; k <= n; ++k)
      if (!std::getline(in, line)) fail(fmt::format("frame {} ends after {} of its {} lines", starts.size() - 1, k, n + 1));
  }
  const std::size_t f = frame_index(path, frame, starts.size());
  in.clear();
  in.seekg(starts[f]);
  std::getline(in, line);
  std::getline(in, line);
  const auto pairs = comment_pairs(line);
  StoredState s;
  s.source = fmt::format("'{}', frame {} of {}", path, f, starts.size());
  s.count = counts[f];
  const auto lattice_text = pairs.find("Lattice");
  if (lattice_text == pairs.end()) fail("its frame has no Lattice (the box)");
  std::vector<double> lattice;
  std::istringstream numbers(lattice_text->second);
  for (double x; numbers >> x;) lattice.push_back(x);
  if (lattice.size() != 9) fail("Lattice does not hold 9 numbers");
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (a != b && lattice[a * 3 + b] != 0) fail("the Lattice is not diagonal; granflow's boxes are rectangular");
  std::array<bool, 3> pbc{true, true, true};
  if (const auto p = pairs.find("pbc"); p != pairs.end()) {
    std::istringstream words(p->second);
    std::string word;
    for (auto& axis : pbc)
      if (words >> word) axis = word == "T" || word == "True" || word == "1";
  }
  // Properties: name:type:columns triples.
  std::string properties = pairs.count("Properties") ? pairs.at("Properties") : "species:S:1:pos:R:3";
  std::map<std::string, std::pair<std::size_t, std::size_t>> column;  // name -> (first column, width)
  {
    std::vector<std::string> fields;
    std::istringstream parts(properties);
    for (std::string part; std::getline(parts, part, ':');) fields.push_back(part);
    if (fields.size() % 3 != 0) fail("its Properties are not name:type:columns triples");
    std::size_t at = 0;
    for (std::size_t k = 0; k < fields.size(); k += 3) {
      const std::size_t width = std::stoul(fields[k + 2]);
      column[fields[k]] = {at, width};
      at += width;
    }
  }
  if (!column.count("pos") || column["pos"].second != 3) fail("its Properties have no pos:R:3 column");
  std::vector<std::vector<std::string>> rows(s.count);
  for (auto& row : rows) {
    std::getline(in, line);
    std::istringstream words(line);
    for (std::string word; words >> word;) row.push_back(word);
  }
  const auto values = [&](const std::string& name, std::size_t width) {
    std::vector<double> out;
    const auto it = column.find(name);
    if (it == column.end()) return out;
    if (it->second.second != width) fail(fmt::format("column {} has {} components, expected {}", name, it->second.second, width));
    for (std::size_t i = 0; i < s.count; ++i)
      for (std::size_t c = 0; c < width; ++c) {
        const std::size_t k = it->second.first + c;
        if (k >= rows[i].size()) fail(fmt::format("particle {} has {} columns, fewer than its Properties", i, rows[i].size()));
        try {
          out.push_back(std::stod(rows[i][k]));
        } catch (const std::exception&) {
          fail(fmt::format("particle {}: column {} is '{}', not a number", i, name, rows[i][k]));
        }
      }
    return out;
  };
  const auto position = values("pos", 3);
  // 2D: every particle in the plane z = 0, not periodic along z.
  bool plane = !pbc[2];
  for (std::size_t i = 0; i < s.count && plane; ++i) plane = position[i * 3 + 2] == 0.0;
  s.dimension = plane ? 2 : 3;
  for (std::size_t a = 0; a < s.dimension; ++a) {
    s.edges.push_back(lattice[a * 4]);
    s.periodic.push_back(pbc[a]);
  }
  auto velocity = values("velo", 3);
  if (velocity.empty()) velocity = values("vel", 3);
  s.mass = values("masses", 1);
  if (s.mass.empty()) s.mass = values("mass", 1);
  if (velocity.empty() && !s.mass.empty()) {
    velocity = values("momenta", 3);
    for (std::size_t k = 0; k < velocity.size(); ++k) velocity[k] /= s.mass[k / 3];
  }
  s.radius = values("radius", 1);
  for (double t : values("typeid", 1)) s.species.push_back(static_cast<std::int64_t>(t));
  for (std::size_t i = 0; i < s.count; ++i)
    for (std::size_t a = 0; a < s.dimension; ++a) {
      s.position.push_back(position[i * 3 + a]);
      if (!velocity.empty()) s.velocity.push_back(velocity[i * 3 + a]);
    }
  return s;
}

enum class StoredFormat { gsd, h5md, xyz };

StoredFormat format_of(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("initial.from = '{}': the file does not exist", path));
  std::ifstream in(path, std::ios::binary);
  std::uint64_t magic = 0;
  in.read(reinterpret_cast<char*>(&magic), sizeof magic);
  in.close();
  if (magic == gsd_magic) return StoredFormat::gsd;
  h5_quiet();
  return H5Fis_hdf5(path.c_str()) > 0 ? StoredFormat::h5md : StoredFormat::xyz;
}

}  // namespace

StoredState read_stored_state(const std::string& path, std::int64_t frame) {
  switch (format_of(path)) {
    case StoredFormat::gsd: return read_gsd(path, frame);
    case StoredFormat::h5md: return read_h5md(path, frame);
    default: return read_xyz(path, frame);
  }
}

StoredFrame::StoredFrame(const std::string& path, std::int64_t frame) : path_(path) {
  in_file_ = format_of(path) == StoredFormat::h5md;
  if (in_file_) {
    state_ = read_h5md(path, frame, false, &frame_, &has_velocity_);
  } else {
    state_ = read_stored_state(path, frame);
    has_velocity_ = !state_.velocity.empty();
  }
}

std::vector<double> StoredFrame::rows(const char* column, const std::vector<double>& held, std::size_t first,
                                      std::size_t count) const {
  const std::size_t width = state_.dimension;
  if (first + count > state_.count) throw std::logic_error("stored frame: rows beyond its particles");
  if (!in_file_)
    return std::vector<double>(held.begin() + static_cast<std::ptrdiff_t>(first * width),
                               held.begin() + static_cast<std::ptrdiff_t>((first + count) * width));
  try {
    return H5mdReader(path_).frame(particles_group + "/" + column + "/value", frame_, first, count).values;
  } catch (const H5Error& error) {
    throw InputError(fmt::format("initial.from = '{}': cannot read its {}: {}", path_, column, error.what()));
  }
}

}  // namespace granflow
