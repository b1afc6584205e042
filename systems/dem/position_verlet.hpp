#pragma once
// Position Verlet (Stoermer's form, e.g. Clewett 2013), the alternative to
// velocity Verlet: x(t + dt) = 2 x(t) - x(t - dt) + F(t) dt^2 / m, and the
// velocity the dampers and observers see is the backward difference
// v(t + dt) = (x(t + dt) - x(t)) / dt. The previous positions are a column
// of their own (unwrapped relative to the current ones, so that a sphere
// crossing a periodic boundary keeps its displacement).

#include <cmath>

#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/image_count.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/vector.hpp"
#include "components/velocity.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/dem/neighbour_list.hpp"

namespace granflow::dem {

inline const SystemDescription dem_position_verlet_description{
    "dem_position_verlet", "position Verlet: x += (x - x_previous) + F dt^2 / m, v the backward difference"};

template <int D>
struct PreviousPosition : Column<Vec<D>> {
  static constexpr const char* key = "previous_position";
};

template <int D>
using DemPositionVerletBase = SystemOf<Reads<Force<D>, Mass, Box<D>, NeighbourList<D>>,
                                       Writes<Position<D>, Velocity<D>, PreviousPosition<D>, ImageCount<D>, Clock>>;

template <int D>
class DemPositionVerlet : public DemPositionVerletBase<D> {
 public:
  using View = typename DemPositionVerletBase<D>::View;
  explicit DemPositionVerlet(double dt) : dt_(dt) {}
  std::string name() const override { return "dem_position_verlet"; }

  // The previous positions of a start from x and v: x - v dt + F dt^2 / 2m,
  // the Taylor step back.
  static void start(World& world, double dt) {
    auto& previous = world.has_component<PreviousPosition<D>>() ? world.component<PreviousPosition<D>>()
                                                                 : world.add_component<PreviousPosition<D>>();
    const auto& x = world.component<Position<D>>();
    const auto& v = world.component<Velocity<D>>();
    const auto& f = world.component<Force<D>>();
    const auto& m = world.component<Mass>();
    for (std::size_t i = 0; i < world.size(); ++i) previous[i] = x[i] - dt * v[i] + (0.5 * dt * dt / m[i]) * f[i];
  }

  void run_on(View view) override {
    auto& clock = view.template write<Clock>();
    clock.advance(dt_);
    auto& x = view.template write<Position<D>>();
    auto& v = view.template write<Velocity<D>>();
    auto& previous = view.template write<PreviousPosition<D>>();
    const auto& f = view.template read<Force<D>>();
    const auto& m = view.template read<Mass>();
    const auto& box = view.template read<Box<D>>();
    auto* images = view.template has<ImageCount<D>>() ? &view.template write<ImageCount<D>>() : nullptr;
    const double dt = dt_;
    const ThreadDomains domains = sphere_domains<D>(view);
    for_each_sphere_run(domains, [&](std::size_t, std::size_t from, std::size_t to) {
      for (std::size_t i = from; i < to; ++i) {
        const Vec<D> next = 2.0 * x[i] - previous[i] + (dt * dt / m[i]) * f[i];
        v[i] = (next - x[i]) / dt;
        previous[i] = x[i];
        x[i] = next;
        const Vec<D> shift = box.wrap(x[i]);
        previous[i] -= shift;
        if (images)
          for (int a = 0; a < D; ++a)
            if (box.periodic[a]) (*images)[i][a] += static_cast<std::int32_t>(std::lround(shift[a] / box.length[a]));
      }
    });
  }

 private:
  double dt_;
};

}  // namespace granflow::dem
