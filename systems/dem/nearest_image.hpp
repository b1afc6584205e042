#pragma once
// The nearest periodic image of a separation d along one axis, for two
// points inside the box (|d| < length): one compare and select each way, so
// loops over pairs stay branch-free and vectorise without rounding
// instructions. half is length / 2 along a periodic axis and infinity along
// the others, which leaves d as it is.

#include "engine/core/host_device.hpp"

namespace granflow::dem {

GRANFLOW_HD inline double nearest_image(double d, double length, double half) {
  const double above = d > half ? length : 0.0;
  const double below = d < -half ? length : 0.0;
  return d - above + below;
}

}  // namespace granflow::dem
