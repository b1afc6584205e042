#pragma once
// The simulation box of every method: [0, L_a) along each axis, each axis
// periodic or closed (by reflecting walls in the event-driven gas, by
// contact walls in DEM).

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "components/vector.hpp"

namespace granflow {

template <int D>
struct Box {
  static constexpr const char* key = "box";
  std::array<double, D> length{};
  std::array<bool, D> periodic{};

  double volume() const {
    double v = 1.0;
    for (double l : length) v *= l;
    return v;
  }
  std::vector<double> edges() const { return {length.begin(), length.end()}; }
  // H5MD's words for the boundary of each axis.
  std::vector<std::string> h5md_boundary() const {
    std::vector<std::string> out;
    for (bool p : periodic) out.push_back(p ? "periodic" : "none");
    return out;
  }

  // Puts p back into the box along the periodic axes; returns what was
  // subtracted (for what moves with p, such as its previous position).
  Vec<D> wrap(Vec<D>& p) const {
    Vec<D> shift = Vec<D>::Zero();
    for (int k = 0; k < D; ++k)
      // Most steps leave a sphere inside: the division only where it left.
      if (periodic[k] && (p[k] < 0.0 || p[k] >= length[k])) {
        shift[k] = length[k] * std::floor(p[k] / length[k]);
        p[k] -= shift[k];
      }
    return shift;
  }

  // Half the box length along the periodic axes, infinity along the others:
  // a separation beyond it is wrapped by nearest_image.
  std::array<double, D> half_periods() const {
    std::array<double, D> half{};
    for (int k = 0; k < D; ++k) half[k] = periodic[k] ? 0.5 * length[k] : std::numeric_limits<double>::infinity();
    return half;
  }

  // The separation a - b, as the minimal image along periodic axes.
  void separation(const Vec<D>& a, const Vec<D>& b, double* out) const {
    for (int k = 0; k < D; ++k) {
      double d = a[k] - b[k];
      if (periodic[k]) {
        if (d > 0.5 * length[k]) d -= length[k];
        else if (d < -0.5 * length[k]) d += length[k];
      }
      out[k] = d;
    }
  }
};

}  // namespace granflow
