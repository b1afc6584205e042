#pragma once
// The random shift of the SRD grid (Ihle & Kroll 2001): every step the cells
// move by one vector uniform in [-1/2, 1/2)^D (in cell sizes), the same for
// every particle, drawn from the run's seed and the step. Without it the
// method is not Galilean invariant at small mean free paths.

#include <array>

#include "components/clock.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_grid_shift_description{
    "srd_grid_shift", "random shift of the SRD grid in [-a/2, a/2)^d each step (Ihle-Kroll), keyed by seed and step"};

template <int D>
class SrdGridShift : public SystemOf<Reads<Clock>, Writes<SrdCells<D>>> {
 public:
  using View = typename SystemOf<Reads<Clock>, Writes<SrdCells<D>>>::View;
  SrdGridShift(std::uint64_t seed, bool enabled) : seed_(seed), enabled_(enabled) {}

  std::string name() const override { return "srd_grid_shift"; }

  void run_on(View view) override {
    draw(view.template write<SrdCells<D>>().shift, seed_, static_cast<std::uint64_t>(view.template read<Clock>().step),
         enabled_);
  }

  // The shift of `step` (zero where the shift is off): what the CPU step and the CUDA step both use.
  static void draw(std::array<double, D>& shift, std::uint64_t seed, std::uint64_t step, bool enabled) {
    if (!enabled) {
      shift.fill(0.0);
      return;
    }
    Philox random(stream::srd_grid_shift, seed, step, 0);
    for (int a = 0; a < D; ++a) shift[a] = random.uniform() - 0.5;
  }

 private:
  std::uint64_t seed_;
  bool enabled_;
};

}  // namespace granflow::srd
