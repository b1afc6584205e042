#include "engine/checkpoint_file.hpp"

#include <fmt/format.h>

#include <vector>

#include "engine/h5md_file.hpp"
#include "engine/h5md_reader.hpp"

namespace granflow {

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
  file.finish();
}

CheckpointContents read_checkpoint(const std::string& path) {
  try {
    const H5mdReader reader(path);
    CheckpointContents out;
    out.configuration = reader.string_dataset("/parameters/toml");
    const auto names = reader.string_array("/checkpoint/names");
    for (std::size_t k = 0; k < names.size(); ++k)
      out.state[names[k]] = reader.doubles("/checkpoint/values/" + std::to_string(k)).values;
    return out;
  } catch (const H5Error& error) {
    throw InputError(fmt::format("--resume: '{}' is not a readable checkpoint ({})", path, error.what()));
  }
}

}  // namespace granflow
