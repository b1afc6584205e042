// srd.device = "cuda": the device step where this build has the CUDA back
// end (GRANFLOW_HAVE_CUDA), else the error that says so. Kept apart from
// the scenarios so that only this file is compiled differently.

#include "systems/srd/srd_setup.hpp"

#if GRANFLOW_HAVE_CUDA
#include "systems/srd/srd_device_step.hpp"
#endif

namespace granflow::srd {

template <int D>
void add_device_step([[maybe_unused]] Run& run, [[maybe_unused]] const SrdCells<D>& cells,
                     [[maybe_unused]] std::size_t particles, [[maybe_unused]] const BodyForce<D>& force,
                     [[maybe_unused]] std::uint64_t reorder_interval, [[maybe_unused]] bool walled) {
#if GRANFLOW_HAVE_CUDA
  const Config& c = run.config();
  if (const std::string why = cuda::srd_device_unavailable(); !why.empty())
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
  run.step<SrdDeviceStep<D>>(p, cells, particles);
#else
  throw ConfigError("srd.device = \"cuda\": this build has no CUDA back end; configure with -DGRANFLOW_CUDA=ON "
                    "(needs nvcc) or use srd.device = \"cpu\"");
#endif
}

template void add_device_step<2>(Run&, const SrdCells<2>&, std::size_t, const BodyForce<2>&, std::uint64_t, bool);
template void add_device_step<3>(Run&, const SrdCells<3>&, std::size_t, const BodyForce<3>&, std::uint64_t, bool);

}  // namespace granflow::srd
