// srd.device = "cuda" or "thrust_host": the device step where this build
// has that back end (GRANFLOW_HAVE_DEVICE_STEP: systems/srd/srd_device.cpp built
// as CUDA, or for Thrust's host back end), else the error that says so. Kept
// apart from the scenarios so that only this file is compiled differently.

#include "systems/srd/srd_setup.hpp"

#include <fmt/format.h>

#include <string>

#if GRANFLOW_HAVE_DEVICE_STEP
#include "systems/srd/srd_device_step.hpp"
#endif

namespace granflow::srd {

template <int D>
void add_device_step([[maybe_unused]] Run& run, [[maybe_unused]] const SrdCells<D>& cells,
                     [[maybe_unused]] std::size_t particles, [[maybe_unused]] const BodyForce<D>& force,
                     [[maybe_unused]] std::uint64_t reorder_interval, [[maybe_unused]] bool walled) {
#if GRANFLOW_HAVE_DEVICE_STEP
  const Config& c = run.config();
  const std::string wanted = c.text("srd.device"), built = device::srd_device_backend();
  if (wanted != built)
    throw ConfigError(fmt::format("srd.device = \"{}\": this build's device step is \"{}\" ({}); use srd.device = "
                                  "\"{}\" or \"cpu\"",
                                  wanted, built,
                                  built == std::string("cuda") ? "configured with -DGRANFLOW_CUDA=ON"
                                                               : "configured without CUDA: -DGRANFLOW_CUDA=ON needs nvcc",
                                  built));
  if (const std::string why = device::srd_device_unavailable(); !why.empty())
    throw ConfigError("srd.device = \"cuda\": " + why + "; use srd.device = \"cpu\" on this machine");
  DeviceStepParameters p;
  p.dt = c.real("srd.time_step");
  p.shear_rate = c.real("shear.rate");
  for (int a = 0; a < D; ++a) p.force.acceleration[a] = force.acceleration[a];
  p.force.slab_axis = force.slab_axis;
  p.force.from = force.from;
  p.force.to = force.to;
  p.rotation = rotation_from(c);
  p.grid_shift = c.boolean("srd.grid_shift");
  p.seed = run.seed();
  p.reorder_interval = reorder_interval;
  p.thermostat = c.real("thermostat.temperature");
  p.thermostat_removes_drift = !walled;
  run.world().template emplace_resource<SrdStepSums<D>>();
  run.step<SrdDeviceStep<D>>(p, cells, particles);
#else
  throw ConfigError(fmt::format("srd.device = \"{}\": this build has no device step (configure with "
                                "-DGRANFLOW_CUDA=ON, which needs nvcc, or install Thrust's headers, Debian's "
                                "libthrust-dev, for \"thrust_host\"); use srd.device = \"cpu\"",
                                run.config().text("srd.device")));
#endif
}

template void add_device_step<2>(Run&, const SrdCells<2>&, std::size_t, const BodyForce<2>&, std::uint64_t, bool);
template void add_device_step<3>(Run&, const SrdCells<3>&, std::size_t, const BodyForce<3>&, std::uint64_t, bool);

}  // namespace granflow::srd
