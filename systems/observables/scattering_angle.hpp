#pragma once
// The lab-frame angle of the small particle's velocity after a two-particle
// collision (observable `scattering_angle`): the projectile is storage index
// 1, as the event-driven gas keeps the order of a two-particle world.

#include <cmath>
#include <string>

#include "components/velocity.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"

namespace granflow {

inline const SystemDescription observe_scattering_angle_description{
    "observe_scattering_angle", "the projectile's lab-frame angle after a two-particle collision"};

class ScatteringAngleObserver : public SystemOf<Reads<Velocity<2>>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Velocity<2>>, Writes<>>::View;
  std::string name() const override { return "observe_scattering_angle"; }
  Access access() const override { return View::access().writes_observable("scattering_angle", unit::angle); }
  void run_on(View view) override {
    const Vec<2> after = view.template read<Velocity<2>>()[1];
    view.observables().set("scattering_angle", std::atan2(std::abs(after.y()), after.x()));
  }
};

}  // namespace granflow
