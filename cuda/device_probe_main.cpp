// Prints whether a CUDA device is usable and, if so, checks one kernel
// against the host. Exit status 0 in both cases; 1 if the kernel disagrees.

#include <cmath>
#include <cstdio>
#include <vector>

#include "cuda/device_query.cuh"

int main() {
  const auto report = granflow::cuda::query_devices();
  std::printf("%s\n", report.message.c_str());
  if (report.count == 0) {
    std::printf("no usable CUDA device: GPU checks skipped\n");
    return 0;
  }
  std::vector<double> mass{1.0, 2.0, 3.0}, speed_squared{0.5, 1.5, 2.5};
  const double device = granflow::cuda::kinetic_energy_on_device(mass.data(), speed_squared.data(), 3);
  const double host = 0.5 * (1.0 * 0.5 + 2.0 * 1.5 + 3.0 * 2.5);
  std::printf("kinetic energy: device %.17g host %.17g\n", device, host);
  return std::abs(device - host) < 1e-14 ? 0 : 1;
}
