#pragma once
// The physics watchdog of an SDE ensemble: it stops the run (exit 3) with a
// diagnosis once the mean squared displacement the observer computed is no
// longer finite (a velocity overflowed), instead of writing a file of
// infinities. Euler-Maruyama past its stability limit gets there; the
// diagnosis names the limit and until when the step is past it.

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "components/clock.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/run/run_control.hpp"

namespace granflow::sde {

inline const SystemDescription watch_sde_description{
    "watch_sde", "stops an SDE run when its mean squared displacement is no longer finite"};

class SdeWatch : public SystemOf<Reads<Clock>, Writes<RunControl>> {
 public:
  // unstable_until: until when the Euler-Maruyama step is past its limit (0: never).
  SdeWatch(double unstable_until, double gamma0_dt) : unstable_until_(unstable_until), gamma0_dt_(gamma0_dt) {}
  std::string name() const override { return "watch_sde"; }
  Access access() const override { return View::access().reads_observable("msd"); }
  void run_on(View view) override {
    const double msd = view.observables().scalar("msd");
    if (std::isfinite(msd)) return;
    const auto& clock = view.read<Clock>();
    const std::string cause =
        unstable_until_ > 0.0
            ? fmt::format("Euler-Maruyama's step is past its stability limit gamma dt < 2 (gamma0 * dt = {:.3g}), so "
                          "velocities grow every step; lower run.dt or use run.scheme = \"exact_ou\"",
                          gamma0_dt_)
            : std::string("check sde.* and run.dt");
    view.write<RunControl>().fail(fmt::format("the SDE run failed at t = {:.6g} (step {}): the mean squared "
                                              "displacement is {} (a velocity overflowed): {}",
                                              clock.time, clock.step, msd, cause));
  }

 private:
  double unstable_until_;
  double gamma0_dt_;
};

}  // namespace granflow::sde
