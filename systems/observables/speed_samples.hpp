#pragma once
// Speeds gathered from one or several snapshots of a gas (snapshots many
// collisions apart are nearly independent samples), per
// species, with their histogram and the mean, rms and most probable speed.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "components/species.hpp"
#include "components/velocity.hpp"
#include "systems/observables/least_squares.hpp"

namespace granflow {

struct SpeedHistogram {
  std::vector<double> edges;    // bins + 1 edges
  std::vector<double> density;  // normalised: sum(density * width) = fraction inside [edges.front(), edges.back()]
};

struct SpeedSummary {
  double mean = 0.0;
  double rms = 0.0;
  double most_probable = 0.0;  // peak of the histogram, refined by a parabola through the top three bins
  std::size_t samples = 0;
};

class SpeedSamples {
 public:
  explicit SpeedSamples(std::size_t species_count = 1) : speeds_(species_count) {}

  // Adds the current speed of every particle, sorted by its Species (all in 0 without one).
  template <int D>
  void add(const Velocity<D>& velocity, const Species* species) {
    for (std::size_t i = 0; i < velocity.size(); ++i) {
      const std::size_t s = species ? std::min<std::size_t>((*species)[i], speeds_.size() - 1) : 0;
      speeds_[s].push_back(velocity[i].norm());
    }
  }

  const std::vector<double>& speeds(std::size_t species = 0) const { return speeds_[species]; }
  std::vector<double> all_speeds() const {
    std::vector<double> all;
    for (const auto& s : speeds_) all.insert(all.end(), s.begin(), s.end());
    return all;
  }
  std::size_t species_count() const { return speeds_.size(); }
  void set_speeds(std::size_t species, std::vector<double> speeds) { speeds_.at(species) = std::move(speeds); }

  // Vertex of a least-squares parabola through the bins above 80 % of the
  // highest one: a smooth peak spans several bins, so this averages out the
  // noise that decides which single bin is highest.
  static double peak_position(const SpeedHistogram& h) {
    const double top = *std::max_element(h.density.begin(), h.density.end());
    const auto highest = static_cast<std::size_t>(std::max_element(h.density.begin(), h.density.end()) - h.density.begin());
    std::size_t lo = highest, hi = highest;
    while (lo > 0 && h.density[lo - 1] >= 0.8 * top) --lo;
    while (hi + 1 < h.density.size() && h.density[hi + 1] >= 0.8 * top) ++hi;
    const double width = h.edges[1] - h.edges[0];
    const double centre = h.edges[highest] + 0.5 * width;
    if (hi - lo < 2) return centre;
    // y = c0 + c1 x + c2 x^2, x in bins relative to the highest bin.
    const auto c = fit_parabola(
        hi - lo + 1, [&](std::size_t k) { return (h.edges[lo + k] + 0.5 * width - centre) / width; },
        [&](std::size_t k) { return h.density[lo + k]; });
    const double c1 = c[1], c2 = c[2];
    if (!(c2 < 0.0)) return centre;
    const double vertex = std::clamp(-c1 / (2.0 * c2), static_cast<double>(lo) - static_cast<double>(highest),
                                     static_cast<double>(hi) - static_cast<double>(highest));
    return centre + vertex * width;
  }

  static SpeedHistogram histogram(const std::vector<double>& speeds, double v_max, int bins) {
    SpeedHistogram h;
    const double width = v_max / bins;
    for (int k = 0; k <= bins; ++k) h.edges.push_back(k * width);
    h.density.assign(static_cast<std::size_t>(bins), 0.0);
    for (double v : speeds) {
      const auto k = static_cast<std::int64_t>(std::floor(v / width));
      if (k >= 0 && k < bins) h.density[static_cast<std::size_t>(k)] += 1.0;
    }
    const double norm = speeds.empty() ? 0.0 : 1.0 / (static_cast<double>(speeds.size()) * width);
    for (double& d : h.density) d *= norm;
    return h;
  }

  static SpeedSummary summarize(const std::vector<double>& speeds, const SpeedHistogram& h) {
    SpeedSummary s;
    s.samples = speeds.size();
    if (speeds.empty()) return s;
    double sum = 0.0, squares = 0.0;
    for (double v : speeds) {
      sum += v;
      squares += v * v;
    }
    s.mean = sum / static_cast<double>(speeds.size());
    s.rms = std::sqrt(squares / static_cast<double>(speeds.size()));
    s.most_probable = peak_position(h);
    return s;
  }

 private:
  std::vector<std::vector<double>> speeds_;
};

}  // namespace granflow
