#pragma once
// Where the mass of a fluid under gravity sits: centre_of_mass_height (the
// mean coordinate along the walls' axis) and peak_cell_density (the most
// particles any cell of this step's grid holds, over the mean n0), which
// grows without bound where the fluid collapses into one dense spot.

#include <algorithm>

#include "components/position.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription observe_srd_height_description{
    "observe_srd_height", "centre_of_mass_height along the walls' axis and peak_cell_density (collapse)"};

template <int D>
class SrdHeightObserver : public SystemOf<Reads<Position<D>, SrdCells<D>>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Position<D>, SrdCells<D>>, Writes<>>::View;
  SrdHeightObserver(int axis, double mean_per_cell) : axis_(axis), mean_per_cell_(mean_per_cell) {}
  std::string name() const override { return "observe_srd_height"; }
  Access access() const override {
    return View::access()
        .writes_observable("centre_of_mass_height", unit::length)
        .writes_observable("peak_cell_density", unit::none);
  }
  // Each rank sums its particles' heights and finds its own cells' peak.
  bool observes_by_rank() const override { return true; }
  void run_on(View view) override {
    const auto& x = view.template read<Position<D>>();
    const auto& cells = view.template read<SrdCells<D>>();
    const ObservedPart& part = view.part();
    const std::vector<double> sums = part.total(
        {deterministic_sum(view.size(), [&](std::size_t i) { return x[i][axis_]; }), static_cast<double>(view.size())});
    std::uint32_t peak = 0;
    for (std::size_t c = 0; c < cells.count.size(); ++c)
      if (cells.owns(c)) peak = std::max(peak, cells.count[c]);
    auto& store = view.observables();
    store.set("centre_of_mass_height", sums[0] / sums[1]);
    store.set("peak_cell_density", part.largest(peak) / mean_per_cell_);
  }

 private:
  int axis_;
  double mean_per_cell_;
};

}  // namespace granflow::srd
