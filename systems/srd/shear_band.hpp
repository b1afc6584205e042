#pragma once
// A shear band (condensation band) in a density profile across the gradient:
// its width, the layers denser than halfway between the median layer (the
// background) and the densest one, in cell sizes; and its contrast, the
// densest layer over the thinnest (infinite once a layer has emptied). A
// homogeneous sheared fluid has contrast 1 + O(1 / sqrt(particles per layer)),
// and its width is that of the noise's few highest layers.

#include <algorithm>
#include <limits>
#include <vector>

namespace granflow::srd {

struct ShearBand {
  double width = 0.0;
  double contrast = 1.0;
};

inline ShearBand shear_band(const std::vector<double>& density) {
  ShearBand band;
  if (density.empty()) return band;
  std::vector<double> sorted = density;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted.size() % 2 ? sorted[sorted.size() / 2]
                                          : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
  const double highest = sorted.back(), lowest = sorted.front();
  const double half = 0.5 * (median + highest);
  band.width = static_cast<double>(std::count_if(density.begin(), density.end(), [&](double d) { return d > half; }));
  band.contrast = lowest > 0 ? highest / lowest : std::numeric_limits<double>::infinity();
  return band;
}

}  // namespace granflow::srd
