#pragma once
// Reports the CUDA devices this process can use, or why it can use none
// (typically: no driver on a build machine).

#include <string>

namespace granflow::cuda {

struct DeviceReport {
  int count = 0;
  std::string message;
};

DeviceReport query_devices();

// Runs one kernel that evaluates a shared host-device function, and returns
// its result for comparison with the host; throws when no device is usable.
double kinetic_energy_on_device(const double* mass, const double* speed_squared, int count);

}  // namespace granflow::cuda
