#pragma once
// Ensemble mean squared displacement <|x(t) - x(0)|^2> over all particles
// (observable `msd`), from unwrapped positions: position + image * L where
// the World has ImageCount (periodic event-driven gases), the position
// itself otherwise (free SDE particles). The sum has a fixed order, so the
// result is the same on any thread count.

#include <array>
#include <string>
#include <vector>

#include "components/box.hpp"
#include "components/image_count.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"

namespace granflow {

inline const SystemDescription observe_msd_description{"observe_msd", "ensemble mean squared displacement from unwrapped positions"};

// Unwrapped positions and particle ids of a world, with the component and
// resource lookups done once rather than per particle.
template <int D>
using UnwrappedView = View<Reads<Position<D>, ImageCount<D>, ParticleId, Box<D>>, Writes<>>;

template <int D>
class UnwrappedPositions {
 public:
  explicit UnwrappedPositions(const UnwrappedView<D>& view)
      : position_(view.template read<Position<D>>().data()),
        image_(view.template has<ImageCount<D>>() ? view.template read<ImageCount<D>>().data() : nullptr),
        id_(view.template has<ParticleId>() ? view.template read<ParticleId>().data() : nullptr) {
    if (image_)
      for (int a = 0; a < D; ++a) length_[a] = view.template read<Box<D>>().length[a];
  }

  Vec<D> operator()(std::size_t i) const {
    Vec<D> u = position_[i];
    if (image_)
      for (int a = 0; a < D; ++a) u[a] += length_[a] * image_[i][a];
    return u;
  }
  // Storage index -> particle id (identity without a ParticleId component).
  std::uint32_t id(std::size_t i) const { return id_ ? id_[i] : static_cast<std::uint32_t>(i); }

 private:
  const Vec<D>* position_;
  const Eigen::Matrix<std::int32_t, D, 1>* image_;
  const std::uint32_t* id_;
  std::array<double, D> length_{};
};

template <int D>
class MsdObserver : public SystemOf<Reads<Position<D>, ImageCount<D>, ParticleId, Box<D>>, Writes<>>, public Stateful {
 public:
  using View = UnwrappedView<D>;
  // Takes the reference positions x(0) from the world as it is now.
  explicit MsdObserver(const World& world) : origin_(world.size()) {
    const UnwrappedPositions<D> unwrapped{View(world)};
    for (std::size_t i = 0; i < world.size(); ++i) origin_[unwrapped.id(i)] = unwrapped(i);
  }

  std::string name() const override { return "observe_msd"; }
  Access access() const override { return View::access().writes_observable("msd", unit::area); }
  StateMap save_state() const override { return {{"origin", flatten_vectors(origin_)}}; }
  void restore_state(const StateMap& state) override { unflatten_vectors(state.at("origin"), origin_, "MSD origins"); }
  void run_on(View view) override { view.observables().set("msd", measure(view)); }

  double measure(const View& view) const {
    const UnwrappedPositions<D> unwrapped(view);
    const double total = deterministic_sum(view.size(), [&](std::size_t i) {
      return (unwrapped(i) - origin_[unwrapped.id(i)]).squaredNorm();
    });
    return view.size() ? total / static_cast<double>(view.size()) : 0.0;
  }

 private:
  std::vector<Vec<D>> origin_;
};

// Diffusivity from an MSD series at (possibly log-spaced) times, the
// time-dependent Einstein relation D = (1 / 2d) dMSD/dt: the mean of the forward and backward
// differences inside, the one-sided difference at the ends.
inline std::vector<double> diffusivity_from_msd(const std::vector<double>& time, const std::vector<double>& msd,
                                                int dimension) {
  const std::size_t n = time.size();
  std::vector<double> out(n, 0.0);
  if (n < 2) return out;
  const auto slope = [&](std::size_t a, std::size_t b) { return (msd[b] - msd[a]) / (time[b] - time[a]); };
  for (std::size_t k = 0; k < n; ++k) {
    const double derivative = k == 0       ? slope(0, 1)
                              : k + 1 == n ? slope(n - 2, n - 1)
                                           : 0.5 * (slope(k - 1, k) + slope(k, k + 1));
    out[k] = derivative / (2.0 * dimension);
  }
  return out;
}

}  // namespace granflow
