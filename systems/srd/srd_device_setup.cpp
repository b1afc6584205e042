// The device step's registration (srd_device_backends.hpp): built into
// granflow_srd_device beside the step's source, so that a build has the
// back end that library was compiled for ("cuda" by nvcc, "thrust_host" by
// the C++ compiler on Thrust's oneTBB back end) and no other file knows it.
// The scenarios' library calls granflow_srd_device_anchor() (generated
// with the scenario anchors) to keep this object in programs linked
// against the static libraries.

#include <string>

#include "systems/srd/srd_device_backends.hpp"
#include "systems/srd/srd_device_step.hpp"
#include "systems/srd/srd_setup.hpp"

namespace granflow::srd {
namespace {

template <int D>
void add(Run& run, const SrdCells<D>& cells, std::size_t particles, const BodyForce<D>& force,
         std::uint64_t reorder_interval, bool walled) {
  const Config& c = run.config();
  DeviceStepParameters p;
  p.dt = c.real("srd.time_step");
  p.shear_rate = c.real("shear.rate");
  p.force = BodyForce<3>(force);
  p.rotation = rotation_from(c);
  p.grid_shift = c.boolean("srd.grid_shift");
  p.seed = run.seed();
  p.reorder_interval = reorder_interval;
  p.thermostat = c.real("thermostat.temperature");
  p.thermostat_removes_drift = !walled;
  run.world().template emplace_resource<SrdStepSums<D>>();
  run.step<SrdDeviceStep<D>>(p, cells, particles);
}

const bool registered = [] {
  const std::string name = device::srd_device_backend();
  register_srd_device_backend({name,
                               name == "cuda" ? "configured with -DGRANFLOW_CUDA=ON"
                                              : "configured without CUDA: -DGRANFLOW_CUDA=ON needs nvcc",
                               device::srd_device_unavailable, add<2>, add<3>});
  return true;
}();

}  // namespace
}  // namespace granflow::srd

extern "C" void granflow_srd_device_anchor() { (void)granflow::srd::registered; }
