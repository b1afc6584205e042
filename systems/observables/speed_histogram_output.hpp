#pragma once
// Writes a speed histogram and its statistics, measured and Maxwell-Boltzmann,
// for the EDMD scenarios that study speed distributions:
//   /results/<name>                  histogram density per bin
//   /results/<name>_edges            bin edges
//   /results/speed_statistics/<name>  attributes: mean, rms and most
//       probable speed, their Maxwell-Boltzmann values at the sample's
//       temperature, and a chi-square test (20 equal-probability bins, 0.999).

#include <string>
#include <vector>

#include "engine/core/units.hpp"
#include "engine/io/h5md_file.hpp"
#include "systems/observables/maxwell_boltzmann.hpp"
#include "systems/observables/speed_samples.hpp"

namespace granflow {

struct SpeedReport {
  SpeedSummary measured;
  double temperature = 0.0;  // from the sampled speeds: m <v^2> / D
  double chi_square = 0.0;
  double chi_square_critical = 0.0;
};

template <int D>
SpeedReport write_speed_histogram(H5mdFile& file, const std::string& name, const std::vector<double>& speeds,
                                  double mass, double v_max, int bins) {
  const auto histogram = SpeedSamples::histogram(speeds, v_max, bins);
  SpeedReport report;
  report.measured = SpeedSamples::summarize(speeds, histogram);
  report.temperature = mass * report.measured.rms * report.measured.rms / D;
  constexpr int test_bins = 20;
  // One parameter (T) is estimated from the same sample.
  report.chi_square_critical = theory::chi_square_critical_0999(test_bins - 2);
  report.chi_square = report.temperature > 0 ? theory::speed_chi_square<D>(speeds, report.temperature, mass, test_bins)
                                             : 0.0;
  file.write_result(name, histogram.density, unit::per_velocity);
  file.write_result(name + "_edges", histogram.edges, unit::velocity);
  const std::string group = "/results/speed_statistics/" + name;
  file.write_attribute(group, "samples", static_cast<double>(report.measured.samples));
  file.write_attribute(group, "mass", mass);
  file.write_attribute(group, "temperature", report.temperature);
  file.write_attribute(group, "mean_speed", report.measured.mean);
  file.write_attribute(group, "rms_speed", report.measured.rms);
  file.write_attribute(group, "most_probable_speed", report.measured.most_probable);
  file.write_attribute(group, "maxwell_boltzmann_mean_speed", theory::mean_speed<D>(report.temperature, mass));
  file.write_attribute(group, "maxwell_boltzmann_rms_speed", theory::rms_speed<D>(report.temperature, mass));
  file.write_attribute(group, "maxwell_boltzmann_most_probable_speed",
                       theory::most_probable_speed<D>(report.temperature, mass));
  file.write_attribute(group, "mean_kinetic_energy", 0.5 * mass * report.measured.rms * report.measured.rms);
  file.write_attribute(group, "chi_square", report.chi_square);
  file.write_attribute(group, "chi_square_critical_0999", report.chi_square_critical);
  return report;
}

}  // namespace granflow
