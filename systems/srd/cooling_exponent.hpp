#pragma once
// The cooling exponent of a granular gas after the transition to
// inhomogeneous cooling: the slope of ln T against ln t by least squares
// over the outputs from the first one whose global Mach number reaches 1
// (the convective energy overtakes the thermal one, where the granular SRD
// study dates the transition) to the end. Haff's law has slope -2 once
// t >> tau; the study measured about -1.55 in the clustering regime.

#include <cmath>
#include <cstddef>
#include <vector>

#include "systems/observables/least_squares.hpp"

namespace granflow::srd {

struct CoolingAfterTransition {
  double transition_time = std::nan("");  // nan: the Mach number never reached 1
  double exponent = std::nan("");
  double exponent_error = std::nan("");   // least-squares error of the slope (the points are not independent)
  std::size_t points = 0;
};

// time, temperature and mach: one entry per output.
inline CoolingAfterTransition cooling_after_transition(const std::vector<double>& time,
                                                       const std::vector<double>& temperature,
                                                       const std::vector<double>& mach) {
  CoolingAfterTransition out;
  std::size_t first = time.size();
  for (std::size_t k = 0; k < time.size() && k < mach.size(); ++k)
    if (mach[k] >= 1.0 && time[k] > 0) {
      first = k;
      break;
    }
  if (first == time.size()) return out;
  out.transition_time = time[first];
  LineFit fit;
  for (std::size_t k = first; k < time.size() && k < temperature.size(); ++k)
    if (time[k] > 0 && temperature[k] > 0) fit.add(std::log(time[k]), std::log(temperature[k]));
  out.points = fit.points();
  out.exponent = fit.slope();
  out.exponent_error = fit.slope_standard_error();
  return out;
}

}  // namespace granflow::srd
