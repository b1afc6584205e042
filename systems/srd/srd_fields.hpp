#pragma once
// Density, velocity and temperature fields of an SRD fluid on the unshifted
// grid (cell k covers [k, k+1) along each axis), averaged over the last
// `window` steps before each output and written to /fields/{density,
// velocity,temperature}/{step,time,value} (value: cells z, y, x [, D]), with
// an XDMF file beside the result file (OUTPUT.fields.xdmf and its companion
// OUTPUT.fields.xdmf.h5) so that ParaView opens the fields on their grid. The
// temperature of a cell is that of each sampled step (about that step's cell
// mean), averaged. Over ranks each rank sums its layers of cells and the
// writing rank, which alone keeps the window's sums, puts them together.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/io/xdmf_export.hpp"
#include "engine/run/output_file.hpp"
#include "engine/run/run.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription write_srd_fields_description{
    "write_srd_fields", "density, velocity and temperature fields on the unshifted grid, window-averaged, to /fields"};

template <int D>
using SrdFieldWriterBase = SystemOf<Reads<Position<D>, Velocity<D>, Mass, Clock, SrdCells<D>>, Writes<OutputFile>>;

template <int D>
class SrdFieldWriter : public SrdFieldWriterBase<D>, public Stateful {
 public:
  using View = typename SrdFieldWriterBase<D>::View;
  SrdFieldWriter(std::array<std::int32_t, D> cells, std::int64_t every, std::int64_t window)
      : cells_(cells), every_(every), window_(std::min(window, every)) {
    std::size_t count = 1;
    for (int a = 0; a < D; ++a) count *= static_cast<std::size_t>(cells[a]);
    particles_.assign(count, 0.0);
    momentum_.assign(count * D, 0.0);
    theta_.assign(count, 0.0);
    theta_samples_.assign(count, 0.0);
    mass_total_.assign(count, 0.0);
  }

  std::string name() const override { return "write_srd_fields"; }

  // Only the steps of a window read the particles.
  bool reads_device_state(const World& world) const override { return in_window(world.resource<Clock>().step); }
  bool observes_by_rank() const override { return true; }

  void run_on(View view) override {
    const auto& clock = view.template read<Clock>();
    if (!in_window(clock.step)) return;
    const std::int64_t phase = clock.step % every_;
    sample(view);
    if (phase != 0) return;
    H5mdFile* file = view.template write<OutputFile>().file;
    if (file) write(*file, clock.step, clock.time);
    std::fill(particles_.begin(), particles_.end(), 0.0);
    std::fill(momentum_.begin(), momentum_.end(), 0.0);
    std::fill(theta_.begin(), theta_.end(), 0.0);
    std::fill(theta_samples_.begin(), theta_samples_.end(), 0.0);
    std::fill(mass_total_.begin(), mass_total_.end(), 0.0);
    samples_ = 0;
  }

  // The window being averaged and the times written, so that a resumed run
  // writes the fields the uninterrupted one would (the frames themselves
  // come back with the file's, engine/run/run.cpp).
  StateMap save_state() const override {
    return {{"particles", particles_}, {"momentum", momentum_}, {"theta", theta_}, {"theta_samples", theta_samples_},
            {"mass", mass_total_}, {"samples", {static_cast<double>(samples_)}}, {"times", times_}};
  }
  void restore_state(const StateMap& state) override {
    const auto take = [&](const char* name, std::vector<double>& to) {
      const auto& from = state.at(name);
      if (from.size() != to.size()) throw std::invalid_argument(std::string("checkpoint field sums '") + name + "' have the wrong size");
      to = from;
    };
    take("particles", particles_);
    take("momentum", momentum_);
    take("theta", theta_);
    take("theta_samples", theta_samples_);
    take("mass", mass_total_);
    samples_ = static_cast<std::int64_t>(state.at("samples").at(0));
    times_ = state.at("times");
  }

  // The XDMF description of the fields written so far, beside the result file.
  void write_xdmf(const H5mdFile& file) const {
    if (times_.empty()) return;
    const std::string xdmf = std::filesystem::path(file.path()).replace_extension(".fields.xdmf").string();
    write_field_xdmf(file.path(), xdmf, std::vector<std::size_t>(cells_.begin(), cells_.end()), times_,
                     {{"density", 1}, {"velocity", static_cast<std::size_t>(D)}, {"temperature", 1}});
  }

 private:
  bool in_window(std::int64_t step) const {
    const std::int64_t phase = step % every_;
    return phase == 0 || phase > every_ - window_;
  }

  // Cell of x on a grid of `dims` cells whose layers along `axis` start at `low`.
  std::size_t grid_cell(const Vec<D>& x, const std::array<std::int32_t, D>& dims, int axis, std::int64_t low) const {
    std::size_t index = 0;
    for (int a = D - 1; a >= 0; --a) {
      auto c = static_cast<std::int64_t>(std::floor(x[a]));
      c = std::min<std::int64_t>(std::max<std::int64_t>(c, 0), cells_[a] - 1);
      if (a == axis) c = std::clamp<std::int64_t>(c - low, 0, dims[a] - 1);
      index = index * static_cast<std::size_t>(dims[a]) + static_cast<std::size_t>(c);
    }
    return index;
  }

  // One step's sums per cell: each rank's over its layers, which the writing
  // rank puts together and the others, which write nothing, let go.
  void sample(const View& view) {
    const auto& x = view.template read<Position<D>>();
    const auto& v = view.template read<Velocity<D>>();
    const double* mass = view.template has<Mass>() ? view.template read<Mass>().data() : nullptr;
    const double m0 = view.template read<SrdCells<D>>().particle_mass;
    const ObservedPart& part = view.part();
    const int axis = part.axis();
    std::array<std::int32_t, D> dims = cells_;
    dims[axis] = static_cast<std::int32_t>(part.layer_high(cells_[axis]) - part.layer_low());
    std::size_t count = 1;
    for (int a = 0; a < D; ++a) count *= static_cast<std::size_t>(dims[a]);
    constexpr std::size_t width = 3 + D;  // particles, mass, sum m v^2, momentum
    std::vector<double> sums(count * width, 0.0);
    for (std::size_t i = 0; i < view.size(); ++i) {
      double* cell = sums.data() + grid_cell(x[i], dims, axis, part.layer_low()) * width;
      const double mi = mass ? mass[i] : m0;
      cell[0] += 1;
      cell[1] += mi;
      cell[2] += mi * v[i].squaredNorm();
      for (int a = 0; a < D; ++a) cell[3 + a] += mi * v[i][a];
    }
    sums = part.whole_field(std::move(sums), std::vector<std::int32_t>(cells_.begin(), cells_.end()), width);
    if (!part.writes()) {
      for (auto* values : {&particles_, &momentum_, &theta_, &theta_samples_, &mass_total_}) std::vector<double>().swap(*values);
      return;
    }
    for (std::size_t c = 0; c < particles_.size(); ++c) {
      const double* cell = sums.data() + c * width;
      const double n = cell[0], m = cell[1], e = cell[2];
      particles_[c] += n;
      for (int a = 0; a < D; ++a) momentum_[c * D + a] += cell[3 + a];
      if (n > 0 && m > 0) {
        double p2 = 0;
        for (int a = 0; a < D; ++a) p2 += cell[3 + a] * cell[3 + a];
        theta_[c] += (e - p2 / m) / (D * n);
        theta_samples_[c] += 1;
      }
      mass_total_[c] += m;
    }
    ++samples_;
  }

  void write(H5mdFile& file, std::int64_t step, double time) {
    if (samples_ == 0) return;
    const std::size_t count = particles_.size();
    std::vector<double> density(count), velocity(count * D, 0.0), temperature(count);
    for (std::size_t c = 0; c < count; ++c) {
      density[c] = particles_[c] / samples_;
      temperature[c] = theta_samples_[c] > 0 ? theta_[c] / theta_samples_[c] : 0.0;
      for (int a = 0; a < D; ++a) velocity[c * D + a] = mass_total_[c] > 0 ? momentum_[c * D + a] / mass_total_[c] : 0.0;
    }
    std::vector<hsize_t> shape;
    for (int a = D - 1; a >= 0; --a) shape.push_back(static_cast<hsize_t>(cells_[a]));
    std::vector<hsize_t> vector_shape = shape;
    vector_shape.push_back(D);
    file.append_field("density", step, time, density, shape, "L-" + std::to_string(D));
    file.append_field("velocity", step, time, velocity, vector_shape, unit::velocity);
    file.append_field("temperature", step, time, temperature, shape, unit::energy);
    times_.push_back(time);
  }

  std::array<std::int32_t, D> cells_;
  std::int64_t every_;
  std::int64_t window_;
  std::vector<double> particles_, momentum_, theta_, theta_samples_, mass_total_;
  std::int64_t samples_ = 0;
  std::vector<double> times_;
};

// Fields every `fields.every_steps` steps (0: none), averaged over `fields.window` steps.
template <int D>
void add_srd_fields(Run& run, std::array<std::int32_t, D> cells) {
  const Config& c = run.config();
  const auto every = c.integer("fields.every_steps");
  if (every <= 0) return;
  auto& writer = run.keep("fields", run.observe<SrdFieldWriter<D>>(std::make_shared<EverySteps>(1, 1), cells, every,
                                                                   c.integer("fields.window")));
  run.at_finish([&writer](H5mdFile& file, const RunOutcome&) { writer.write_xdmf(file); });
}

// Compiled once for both dimensions, in srd_fields.cpp, for every scenario that writes fields.
extern template void add_srd_fields<2>(Run&, std::array<std::int32_t, 2>);
extern template void add_srd_fields<3>(Run&, std::array<std::int32_t, 3>);

}  // namespace granflow::srd
