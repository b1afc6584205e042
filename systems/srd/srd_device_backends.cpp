#include "systems/srd/srd_device_backends.hpp"

#include <map>

namespace granflow::srd {

namespace {
std::map<std::string, SrdDeviceBackend>& backends() {
  static std::map<std::string, SrdDeviceBackend> registered;
  return registered;
}
}  // namespace

void register_srd_device_backend(const SrdDeviceBackend& backend) { backends()[backend.name] = backend; }

const SrdDeviceBackend* find_srd_device_backend(const std::string& name) {
  const auto it = backends().find(name);
  return it == backends().end() ? nullptr : &it->second;
}

std::vector<std::string> srd_device_backend_names() {
  std::vector<std::string> names;
  for (const auto& [name, backend] : backends()) names.push_back(name);
  return names;
}

}  // namespace granflow::srd
