#pragma once
// The back ends of the SRD step's device path (srd.device other than "cpu"),
// as the library that builds one registers itself (srd_device_setup.cpp, in
// granflow_srd_device): the SRD setup picks one by name and includes none,
// as the Runner picks a scenario. A build without one refuses the key with
// the way to get one.

#include <fmt/format.h>

#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/config.hpp"
#include "engine/run/run.hpp"
#include "systems/srd/srd_cells.hpp"
#include "systems/srd/srd_walls.hpp"

namespace granflow::srd {

// Adds the device step in place of the CPU systems.
template <int D>
using AddDeviceStep = void (*)(Run& run, const SrdCells<D>& cells, std::size_t particles, const BodyForce<D>& force,
                               std::uint64_t reorder_interval, bool walled);

struct SrdDeviceBackend {
  std::string name;          // the srd.device value
  std::string configured;    // how this build got it, for messages
  std::string (*unavailable)();  // empty where it can run on this machine; else why not
  AddDeviceStep<2> add_2d;
  AddDeviceStep<3> add_3d;
};

void register_srd_device_backend(const SrdDeviceBackend& backend);
// Null where this build has no back end of that name.
const SrdDeviceBackend* find_srd_device_backend(const std::string& name);
std::vector<std::string> srd_device_backend_names();

// The device step of srd.device, or the error that says why it cannot run.
template <int D>
void add_device_step(Run& run, const SrdCells<D>& cells, std::size_t particles, const BodyForce<D>& force,
                     std::uint64_t reorder_interval, bool walled) {
  const std::string wanted = run.config().text("srd.device");
  const SrdDeviceBackend* backend = find_srd_device_backend(wanted);
  if (!backend) {
    const auto names = srd_device_backend_names();
    if (names.empty())
      throw ConfigError(fmt::format("srd.device = \"{}\": this build has no device step (configure with "
                                    "-DGRANFLOW_CUDA=ON, which needs nvcc, or install Thrust's headers, Debian's "
                                    "libthrust-dev, for \"thrust_host\"); use srd.device = \"cpu\"",
                                    wanted));
    const SrdDeviceBackend& built = *find_srd_device_backend(names.front());
    throw ConfigError(fmt::format("srd.device = \"{}\": this build's device step is \"{}\" ({}); use srd.device = "
                                  "\"{}\" or \"cpu\"",
                                  wanted, built.name, built.configured, built.name));
  }
  if (const std::string why = backend->unavailable(); !why.empty())
    throw ConfigError(fmt::format("srd.device = \"{}\": {}; use srd.device = \"cpu\" on this machine", wanted, why));
  if constexpr (D == 2)
    backend->add_2d(run, cells, particles, force, reorder_interval, walled);
  else
    backend->add_3d(run, cells, particles, force, reorder_interval, walled);
}

}  // namespace granflow::srd
