#pragma once
// The distribution of the reduced speed c = |v - <v>| / v_T, v_T = sqrt(2 T_g / m)
// (T_g the granular temperature, m the mean mass): the variable of the
// kinetic theory of granular gases, in which the Maxwellian is
// f(c) = 4 pi^{-1/2} c^2 exp(-c^2) in 3D and 2 c exp(-c^2) in 2D and the
// homogeneous cooling state deviates from it by the Sonine series (a2, a3:
// srd_state_observer.hpp). Written as the observable velocity_distribution,
// a probability density over `bins` bins of equal width in [0, c_max).

#include <cmath>
#include <vector>

#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/global_motion.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription observe_velocity_distribution_description{
    "observe_velocity_distribution", "distribution of the reduced speed c = |v - <v>| / sqrt(2 T_g / m) (SRD)"};

inline constexpr double reduced_speed_max = 4.0;  // f(4) / f_max < 1e-5 for a Maxwellian

template <int D>
class VelocityDistributionObserver : public SystemOf<Reads<Velocity<D>, Mass, SrdCells<D>>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Velocity<D>, Mass, SrdCells<D>>, Writes<>>::View;
  explicit VelocityDistributionObserver(std::size_t bins) : bins_(bins) {}

  std::string name() const override { return "observe_velocity_distribution"; }
  Access access() const override {
    return View::access().writes_observable("velocity_distribution", unit::none);
  }

  // Each rank bins its own particles; the counts are added over the ranks.
  bool observes_by_rank() const override { return true; }

  void run_on(View view) override {
    const auto& velocity = view.template read<Velocity<D>>();
    const std::size_t n = view.size();
    const GlobalMotion<D> global = observed_motion<D>(view, view.template read<SrdCells<D>>().particle_mass);
    const Vec<D>& mean = global.mean;
    const double granular = global.granular_temperature;
    std::vector<double> density(bins_, 0.0);
    const double scale = granular > 0 ? 1.0 / std::sqrt(2.0 * granular / (global.total_mass / global.particles)) : 0.0;
    const double width = reduced_speed_max / static_cast<double>(bins_);
    // Integer counts: the histogram is exact, so the order does not matter.
    for (std::size_t i = 0; i < n; ++i) {
      const double c = (velocity[i] - mean).norm() * scale;
      const auto bin = static_cast<std::size_t>(c / width);
      if (bin < bins_) density[bin] += 1.0;
    }
    density = view.part().total(density);
    for (double& value : density) value /= global.particles * width;
    view.observables().set("velocity_distribution", std::move(density));
  }

  // The bins' centres, for the file's attribute.
  std::vector<double> centres() const {
    std::vector<double> out(bins_);
    const double width = reduced_speed_max / static_cast<double>(bins_);
    for (std::size_t k = 0; k < bins_; ++k) out[k] = (static_cast<double>(k) + 0.5) * width;
    return out;
  }

 private:
  std::size_t bins_;
};

}  // namespace granflow::srd
