#pragma once
// The simulation box: [0, L_a) along each axis, each axis periodic or bounded
// by reflecting walls.

#include <array>
#include <string>
#include <vector>

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
};

}  // namespace granflow
