#include "engine/io/checkpoint_file.hpp"

#include <fmt/format.h>

#include <vector>

#include "engine/io/file_seal.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/io/h5md_reader.hpp"

namespace granflow {

namespace {

// FNV-1a over the configuration and every array, name and bytes: any change
// to a stored value, however small, changes it.
std::string checksum_of(const std::string& configuration, const StateMap& state) {
  std::uint64_t hash = 14695981039346656037ull;
  const auto mix = [&](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) hash = (hash ^ p[k]) * 1099511628211ull;
  };
  mix(configuration.data(), configuration.size());
  for (const auto& [name, values] : state) {
    mix(name.data(), name.size() + 1);
    const std::uint64_t count = values.size();
    mix(&count, sizeof count);
    mix(values.data(), values.size() * sizeof(double));
  }
  return fmt::format("fnv1a64:{:016x}", hash);
}

}  // namespace

void write_checkpoint(const std::string& path, const std::string& scenario, const Config& config,
                      const StateMap& state) {
  H5mdFile file(path, scenario + " checkpoint");
  file.write_parameters(config);
  std::vector<std::string> names;
  std::size_t k = 0;
  for (const auto& [name, values] : state) {
    names.push_back(name);
    file.write_array("/checkpoint/values", std::to_string(k++), values);
  }
  file.write_text_array("/checkpoint", "names", names);
  file.write_attribute("/checkpoint", "checksum", checksum_of(config.to_toml(), state));
  file.finish();
}

CheckpointContents read_checkpoint(const std::string& path) {
  try {
    if (const SealState seal = check_seal(path); seal != SealState::matches)
      throw H5Error("the file " + describe(seal));
    const H5mdReader reader(path);
    CheckpointContents out;
    out.configuration = reader.string_dataset("/parameters/toml");
    const auto names = reader.string_array("/checkpoint/names");
    for (std::size_t k = 0; k < names.size(); ++k)
      if (!out.state.emplace(names[k], reader.doubles("/checkpoint/values/" + std::to_string(k)).values).second)
        throw H5Error("array '" + names[k] + "' is listed twice");
    if (reader.string_attribute("/checkpoint", "checksum") != checksum_of(out.configuration, out.state))
      throw H5Error("its contents do not match their checksum: the file was changed or damaged");
    return out;
  } catch (const H5Error& error) {
    throw InputError(fmt::format("--resume: '{}' is not a usable checkpoint: {}; delete it to start afresh", path,
                                 error.what()));
  }
}

}  // namespace granflow
