#include "engine/io/gsd_export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <vector>

#include "engine/core/input_error.hpp"
#include "engine/io/gsd_layout.hpp"
#include "engine/io/particle_frames.hpp"

namespace granflow {

namespace {

class GsdWriter {
 public:
  explicit GsdWriter(const std::string& path) : path_(path), partial_(path + ".partial") {
    out_ = std::fopen(partial_.c_str(), "wb");
    if (!out_) throw InputError(fmt::format("cannot write '{}'", partial_));
    const GsdHeader placeholder;
    put(&placeholder, sizeof placeholder);
  }
  ~GsdWriter() {
    if (out_) {
      std::fclose(out_);
      std::error_code ignored;
      std::filesystem::remove(partial_, ignored);
    }
  }

  template <class T>
  void chunk(const std::string& name, GsdType type, std::uint64_t rows, std::uint32_t columns,
             const std::vector<T>& data) {
    auto [it, added] = names_.try_emplace(name, static_cast<std::uint16_t>(names_.size()));
    if (added) name_order_.push_back(name);
    pending_.push_back({frame_, rows, offset_, columns, it->second, static_cast<std::uint8_t>(type), 0});
    put(data.data(), data.size() * sizeof(T));
  }
  void end_frame() {
    std::stable_sort(pending_.begin(), pending_.end(),
                     [](const GsdIndexEntry& a, const GsdIndexEntry& b) { return a.name < b.name; });
    index_.insert(index_.end(), pending_.begin(), pending_.end());
    pending_.clear();
    ++frame_;
  }

  void finish(const std::string& application, const std::string& schema, std::uint32_t schema_version) {
    GsdHeader header;
    header.gsd_version = gsd_version(2, 0);
    header.schema_version = schema_version;
    std::strncpy(header.application, application.c_str(), sizeof header.application - 1);
    std::strncpy(header.schema, schema.c_str(), sizeof header.schema - 1);
    std::vector<char> names;
    for (const auto& name : name_order_) names.insert(names.end(), name.c_str(), name.c_str() + name.size() + 1);
    names.resize((names.size() / 64 + 1) * 64, 0);  // ends in at least one 0: the list's end
    header.namelist_location = static_cast<std::uint64_t>(offset_);
    header.namelist_allocated_entries = names.size() / 64;
    put(names.data(), names.size());
    // A spare entry of location 0 marks the end of the index.
    header.index_location = static_cast<std::uint64_t>(offset_);
    header.index_allocated_entries = std::max<std::uint64_t>(index_.size() + 1, frame_ + 1);
    index_.resize(header.index_allocated_entries, GsdIndexEntry{0, 0, 0, 0, 0, 0, 0});
    put(index_.data(), index_.size() * sizeof(GsdIndexEntry));
    if (std::fseek(out_, 0, SEEK_SET) != 0) fail();
    put(&header, sizeof header);
    const bool written = std::fflush(out_) == 0 && !std::ferror(out_);
    std::fclose(std::exchange(out_, nullptr));
    if (!written) {
      std::filesystem::remove(partial_);
      throw InputError(fmt::format("cannot write '{}' (disk full?)", partial_));
    }
    std::filesystem::rename(partial_, path_);
  }

 private:
  void put(const void* data, std::size_t bytes) {
    if (bytes && std::fwrite(data, 1, bytes, out_) != bytes) fail();
    offset_ += static_cast<std::int64_t>(bytes);
  }
  [[noreturn]] void fail() const { throw InputError(fmt::format("cannot write '{}' (disk full?)", partial_)); }

  std::string path_, partial_;
  std::FILE* out_ = nullptr;
  std::int64_t offset_ = 0;
  std::uint64_t frame_ = 0;
  std::map<std::string, std::uint16_t> names_;
  std::vector<std::string> name_order_;
  std::vector<GsdIndexEntry> pending_, index_;
};

}  // namespace

std::size_t export_gsd(const std::string& result, const std::string& output) {
  const H5mdReader reader(result);
  const auto frames = ParticleFrames::read(reader, result);
  const std::size_t n = frames.count, d = frames.dimension;
  const std::string& p = particles_group;
  GsdWriter gsd(output);
  for (std::size_t f = 0; f < frames.frames; ++f) {
    const auto edges = frames.edges(f);
    const auto edge = [&](std::size_t a) { return a < edges.size() ? edges[a] : 0.0; };
    gsd.chunk("configuration/step", GsdType::uint64, 1, 1,
              std::vector<std::uint64_t>{static_cast<std::uint64_t>(std::max<std::int64_t>(frames.steps[f], 0))});
    gsd.chunk("configuration/dimensions", GsdType::uint8, 1, 1, std::vector<std::uint8_t>{static_cast<std::uint8_t>(d)});
    gsd.chunk("configuration/box", GsdType::float32, 6, 1,
              std::vector<float>{static_cast<float>(edge(0)), static_cast<float>(edge(1)),
                                 d == 3 ? static_cast<float>(edge(2)) : 0.0f, 0.0f, 0.0f, 0.0f});
    gsd.chunk("particles/N", GsdType::uint32, 1, 1, std::vector<std::uint32_t>{static_cast<std::uint32_t>(n)});
    const auto position = reader.frame(p + "/position/value", f).values;
    std::vector<float> centred(n * 3, 0.0f);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t a = 0; a < d; ++a) centred[i * 3 + a] = static_cast<float>(position[i * d + a] - 0.5 * edge(a));
    gsd.chunk("particles/position", GsdType::float32, n, 3, centred);
    if (frames.has_velocity) {
      const auto velocity = reader.frame(p + "/velocity/value", f).values;
      std::vector<float> padded(n * 3, 0.0f);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t a = 0; a < d; ++a) padded[i * 3 + a] = static_cast<float>(velocity[i * d + a]);
      gsd.chunk("particles/velocity", GsdType::float32, n, 3, padded);
    }
    if (frames.has_image) {
      const auto image = reader.frame(p + "/image/value", f).values;
      std::vector<std::int32_t> padded(n * 3, 0);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t a = 0; a < d; ++a) padded[i * 3 + a] = static_cast<std::int32_t>(image[i * d + a]);
      gsd.chunk("particles/image", GsdType::int32, n, 3, padded);
    }
    if (f == 0) {
      std::vector<std::uint32_t> typeid_(n, 0);
      if (frames.species)
        for (std::size_t i = 0; i < n; ++i) typeid_[i] = static_cast<std::uint32_t>((*frames.species)[i]);
      const std::uint32_t types = n ? *std::max_element(typeid_.begin(), typeid_.end()) + 1 : 1;
      // Type names as a [types, width] array of 0-terminated characters.
      const std::size_t width = fmt::format("{}", types - 1).size() + 1;
      std::vector<std::int8_t> names(types * width, 0);
      for (std::uint32_t t = 0; t < types; ++t) {
        const std::string name = fmt::format("{}", t);
        std::copy(name.begin(), name.end(), names.begin() + static_cast<std::ptrdiff_t>(t * width));
      }
      gsd.chunk("particles/types", GsdType::int8, types, static_cast<std::uint32_t>(width), names);
      gsd.chunk("particles/typeid", GsdType::uint32, n, 1, typeid_);
      if (frames.mass) gsd.chunk("particles/mass", GsdType::float32, n, 1, std::vector<float>(frames.mass->begin(), frames.mass->end()));
      if (frames.radius) {
        std::vector<float> diameter(n);
        for (std::size_t i = 0; i < n; ++i) diameter[i] = static_cast<float>(2.0 * (*frames.radius)[i]);
        gsd.chunk("particles/diameter", GsdType::float32, n, 1, diameter);
      }
    }
    gsd.chunk("log/time", GsdType::float64, 1, 1, std::vector<double>{frames.times[f]});
    gsd.end_frame();
  }
  gsd.finish("granflow", "hoomd", gsd_version(1, 4));
  return frames.frames;
}

}  // namespace granflow
