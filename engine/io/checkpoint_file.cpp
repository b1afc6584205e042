#include "engine/io/checkpoint_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "engine/core/input_error.hpp"
#include "engine/io/file_seal.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/io/h5md_reader.hpp"

namespace granflow {

namespace {

// Rows a block of the particle arrays carries between ranks, and values a
// read of one holds: a few MB, whatever the system's size.
constexpr std::size_t rows_per_block = std::size_t{1} << 18;
constexpr std::size_t values_per_read = std::size_t{1} << 20;

// FNV-1a over the configuration and every array in name order, name, count
// and values: any change to a stored value, however small, changes it.
// Fed in pieces, so that an array written or read in blocks is hashed
// block by block.
class Checksum {
 public:
  explicit Checksum(const std::string& configuration) { mix(configuration.data(), configuration.size()); }
  void begin_array(const std::string& name, std::uint64_t count) {
    mix(name.data(), name.size() + 1);
    mix(&count, sizeof count);
  }
  void values(const std::vector<double>& values) { mix(values.data(), values.size() * sizeof(double)); }
  std::string text() const { return fmt::format("fnv1a64:{:016x}", hash_); }

 private:
  void mix(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) hash_ = (hash_ ^ p[k]) * 1099511628211ull;
  }
  std::uint64_t hash_ = 14695981039346656037ull;
};

// The file's list of arrays, /checkpoint/values/<index> in name order, and
// the checksum over them: what both writers share.
class CheckpointWriter {
 public:
  CheckpointWriter(const std::string& path, const std::string& scenario, const Config& config)
      : file_(path, scenario + " checkpoint"), checksum_(config.to_toml()) {
    file_.write_parameters(config);
  }
  void array(const std::string& name, const std::vector<double>& values) {
    checksum_.begin_array(name, values.size());
    checksum_.values(values);
    file_.write_array("/checkpoint/values", next_index(name), values);
  }
  void begin_array(const std::string& name, std::size_t count) {
    checksum_.begin_array(name, count);
    open_ = next_index(name);
    file_.create_array("/checkpoint/values", open_, count);
  }
  // The open array's next values from `first`, in order.
  void block(std::size_t first, const std::vector<double>& values) {
    checksum_.values(values);
    file_.write_array_block("/checkpoint/values", open_, first, values);
  }
  void finish() {
    file_.write_text_array("/checkpoint", "names", names_);
    file_.write_attribute("/checkpoint", "checksum", checksum_.text());
    file_.finish();
  }

 private:
  std::string next_index(const std::string& name) {
    names_.push_back(name);
    return std::to_string(names_.size() - 1);
  }
  H5mdFile file_;
  Checksum checksum_;
  std::vector<std::string> names_;
  std::string open_;
};

}  // namespace

bool holds_particle_rows(const std::string& name) {
  constexpr std::string_view prefix = "world/", width = ".width", kept = "kept/", rows = "/rows/";
  const std::string_view n = name;
  if (n.starts_with(kept)) return n.find(rows) != std::string_view::npos;
  return n.size() > prefix.size() && n.starts_with(prefix) && !n.ends_with(width);
}

void write_checkpoint(const std::string& path, const std::string& scenario, const Config& config,
                      const StateMap& state) {
  CheckpointWriter writer(path, scenario, config);
  for (const auto& [name, values] : state) writer.array(name, values);
  writer.finish();
}

void write_checkpoint_by_rank(const std::string& path, const std::string& scenario, const Config& config,
                              const StateMap& state, const RankRows& rows, const Communicator& ranks) {
  const bool first = ranks.rank() == 0;
  // Every array's rows on every rank, in one exchange: [rank][array].
  std::vector<double> mine_counts;
  for (const auto& entry : rows.arrays) mine_counts.push_back(static_cast<double>(rows.rows_of(entry.first)));
  const std::vector<double> counts = ranks.gather_all(mine_counts);
  const std::size_t arrays = rows.arrays.size();
  if (counts.size() != arrays * static_cast<std::size_t>(ranks.size()))
    throw std::logic_error("checkpoint by rank: the ranks hold different row arrays");
  std::optional<CheckpointWriter> writer;
  if (first) writer.emplace(path, scenario, config);
  // Rank 0 lists the whole state's arrays and the row arrays in one name
  // order; every rank meets the row arrays in that order, and they alone
  // are collective.
  auto whole = state.begin();
  const auto write_whole_before = [&](const std::string* name) {
    if (!first) return;
    for (; whole != state.end() && (!name || whole->first < *name); ++whole) {
      if (rows.arrays.count(whole->first))
        throw std::logic_error("checkpoint array '" + whole->first + "' is both whole and in rows");
      writer->array(whole->first, whole->second);
    }
  };
  std::size_t array = 0;
  for (const auto& [name, mine] : rows.arrays) {
    write_whole_before(&name);
    std::size_t offset = 0, total = 0;
    for (std::size_t r = 0; r < static_cast<std::size_t>(ranks.size()); ++r) {
      const auto held = static_cast<std::size_t>(counts[r * arrays + array]);
      if (static_cast<int>(r) < ranks.rank()) offset += held;
      total += held;
    }
    const std::size_t count = rows.rows_of(name);
    ++array;
    const auto values = static_cast<std::size_t>(ranks.sum(static_cast<std::int64_t>(mine.size())));
    const std::size_t width = total > 0 ? values / total : 0;
    if (width * total != values || (count > 0 && mine.size() != width * count))
      throw std::logic_error(fmt::format("checkpoint array '{}': {} values over {} rows", name, values, total));
    if (first) writer->begin_array(name, values);
    for (std::size_t block_first = 0; block_first < total; block_first += rows_per_block) {
      const std::size_t block_end = std::min(total, block_first + rows_per_block);
      const std::size_t from = std::clamp(block_first, offset, offset + count);
      const std::size_t to = std::clamp(block_end, offset, offset + count);
      const auto begin = mine.begin() + static_cast<std::ptrdiff_t>((from - offset) * width);
      const std::vector<double> block =
          ranks.gather_to_first(std::vector<double>(begin, begin + static_cast<std::ptrdiff_t>((to - from) * width)));
      if (!first) continue;
      if (block.size() != (block_end - block_first) * width)
        throw std::logic_error(fmt::format("checkpoint array '{}': {} values of rows {}..{} arrived", name,
                                           block.size(), block_first, block_end - 1));
      writer->block(block_first * width, block);
    }
  }
  write_whole_before(nullptr);
  if (first) writer->finish();
}

std::map<std::string, std::size_t> CheckpointRows::sizes() const {
  std::map<std::string, std::size_t> out;
  for (const auto& [name, dataset] : datasets_) out[name] = dataset.size;
  return out;
}

std::vector<double> CheckpointRows::read(const std::string& name, std::size_t first, std::size_t count) const {
  const auto found = datasets_.find(name);
  if (found == datasets_.end()) throw std::logic_error("checkpoint has no row array '" + name + "'");
  try {
    return H5mdReader(file_).doubles(found->second.path, first, count);
  } catch (const H5Error& error) {
    throw InputError(fmt::format("--resume: '{}' is not a usable checkpoint: {}; delete it to start afresh", file_,
                                 error.what()));
  }
}

CheckpointContents read_checkpoint(const std::string& path, const CheckpointReading& how) {
  try {
    if (how.check)
      if (const SealState seal = check_seal(path); seal != SealState::matches)
        throw H5Error("the file " + describe(seal));
    const H5mdReader reader(path);
    CheckpointContents out;
    out.configuration = reader.string_dataset("/parameters/toml");
    out.rows = CheckpointRows(path);
    const auto names = reader.string_array("/checkpoint/names");
    std::vector<std::size_t> in_name_order(names.size());
    for (std::size_t k = 0; k < names.size(); ++k) in_name_order[k] = k;
    std::sort(in_name_order.begin(), in_name_order.end(), [&](std::size_t a, std::size_t b) {
      return names[a] < names[b];
    });
    Checksum checksum(out.configuration);
    for (std::size_t k : in_name_order) {
      const std::string& name = names[k];
      const std::string dataset = "/checkpoint/values/" + std::to_string(k);
      if (out.state.count(name) || out.rows.holds(name))
        throw H5Error("array '" + name + "' is listed twice");
      if (!how.particle_rows_by_block || !holds_particle_rows(name)) {
        const auto& values = out.state.emplace(name, reader.doubles(dataset).values).first->second;
        checksum.begin_array(name, values.size());
        checksum.values(values);
        continue;
      }
      const auto shape = reader.shape(dataset);
      if (shape.size() != 1) throw H5Error("array '" + name + "' is not a list of values");
      out.rows.add(name, dataset, shape[0]);
      if (!how.check) continue;
      checksum.begin_array(name, shape[0]);
      for (std::uint64_t first = 0; first < shape[0]; first += values_per_read)
        checksum.values(reader.doubles(dataset, first, std::min<std::uint64_t>(values_per_read, shape[0] - first)));
    }
    if (how.check && reader.string_attribute("/checkpoint", "checksum") != checksum.text())
      throw H5Error("its contents do not match their checksum: the file was changed or damaged");
    return out;
  } catch (const H5Error& error) {
    throw InputError(fmt::format("--resume: '{}' is not a usable checkpoint: {}; delete it to start afresh", path,
                                 error.what()));
  }
}

}  // namespace granflow
