// The shared GRANFLOW_HD functions give the same results on the device as on
// the host: Philox words bit for bit (integer arithmetic), one pair
// collision to 1e-14 relative (double arithmetic; the device may fuse
// multiply-adds), one SDE step to 1e-6 of its noise term (the device's float
// log and cos against the host's, a few ulp), one SRD step of streaming,
// walls, cell index and collision to 1e-12. Skips, saying why, where no
// CUDA device is usable.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cuda/device_query.cuh"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "systems/edmd/collision_rule.hpp"
#include "systems/sde/gaussian_noise.hpp"
#include "systems/sde/sde_model.hpp"
#include "tests/gpu/host_device_check.cuh"
#include "tests/gpu/srd_check_step.cuh"

namespace granflow::cuda {
namespace {

// Empty when a device is usable, else why not.
std::string no_device() {
  const auto report = query_devices();
  return report.count > 0 ? "" : "no usable CUDA device (" + report.message + "): GPU check skipped";
}

TEST(HostDevice, PhiloxWordsAreIdentical) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  constexpr int count = 4096;
  std::vector<std::uint32_t> device(4 * count);
  philox_words_on_device(stream::sde_noise, 0x1234567890ull, 77, count, device.data());
  for (int i = 0; i < count; ++i) {
    const auto host = Philox(stream::sde_noise, 0x1234567890ull, 77, static_cast<std::uint64_t>(i)).next_words();
    for (int k = 0; k < 4; ++k) ASSERT_EQ(device[4 * i + k], host[k]) << "item " << i;
  }
}

TEST(HostDevice, SdeStepAgrees) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  constexpr int count = 2048;
  for (int scheme : {0, 1}) {
    const SdeCheckInput in{2.0, 0.3, 1.0, 1.5, 0.01, 99, 12, scheme};
    std::vector<double> x(count), v(count);
    for (int i = 0; i < count; ++i) {
      x[i] = 0.01 * i;
      v[i] = std::sin(static_cast<double>(i));
    }
    std::vector<double> xd = x, vd = v;
    sde_step_on_device(in, count, xd.data(), vd.data());
    sde::SdeModel model;
    model.gamma0 = in.gamma0;
    model.diffusivity0 = in.diffusivity0;
    model.tau0 = in.tau0;
    for (int i = 0; i < count; ++i) {
      std::uint32_t c0 = static_cast<std::uint32_t>(i), c1 = 0, c2 = 12, c3 = stream::sde_noise << 16;
      sde::philox4x32_10(c0, c1, c2, c3, 99, 0);
      const float noise = sde::box_muller_radius(c0) * std::cos(sde::box_muller_angle(c1));
      double xh = x[i], vh = v[i], xq = x[i], vq = v[i];
      if (scheme == 1) {
        sde::euler_maruyama_step(xh, vh, model.friction(in.time), model.diffusivity(in.time), in.dt, noise);
        sde::euler_maruyama_step(xq, vq, model.friction(in.time), model.diffusivity(in.time), in.dt, 0.0f);
      } else {
        const auto ou = sde::exact_velocity_update(model, in.time, in.dt);
        sde::drift_ou_drift_step(xh, vh, ou, in.dt, noise);
        sde::drift_ou_drift_step(xq, vq, ou, in.dt, 0.0f);
      }
      ASSERT_LE(std::abs(vd[i] - vh), 1e-6 * std::abs(vh - vq) + 1e-15) << "scheme " << scheme << " particle " << i;
      ASSERT_LE(std::abs(xd[i] - xh), 1e-6 * std::abs(xh - xq) + 1e-15) << "scheme " << scheme << " particle " << i;
    }
  }
}

TEST(HostDevice, PairCollisionAgrees) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  constexpr int count = 1000;
  std::vector<double> mass(2 * count), dx(3 * count), v(6 * count);
  for (int i = 0; i < count; ++i) {
    mass[2 * i] = 1.0 + 0.01 * i;
    mass[2 * i + 1] = 2.0;
    for (int a = 0; a < 3; ++a) {
      dx[3 * i + a] = std::cos(1.0 + i + a);
      v[6 * i + a] = std::sin(2.0 + i + a);
      v[6 * i + 3 + a] = std::sin(3.0 * i - a);
    }
  }
  std::vector<double> vd = v, lost(count);
  pair_collisions_on_device(count, 0.8, mass.data(), dx.data(), vd.data(), lost.data());
  for (int i = 0; i < count; ++i) {
    Vec<3> vi(v[6 * i], v[6 * i + 1], v[6 * i + 2]), vj(v[6 * i + 3], v[6 * i + 4], v[6 * i + 5]);
    const Vec<3> separation(dx[3 * i], dx[3 * i + 1], dx[3 * i + 2]);
    const auto host = edmd::collide_pair<3>(vi, vj, mass[2 * i], mass[2 * i + 1], separation, 0.8);
    const double scale = vi.norm() + vj.norm();
    for (int a = 0; a < 3; ++a) {
      ASSERT_NEAR(vd[6 * i + a], vi[a], 1e-14 * scale) << "pair " << i;
      ASSERT_NEAR(vd[6 * i + 3 + a], vj[a], 1e-14 * scale) << "pair " << i;
    }
    ASSERT_NEAR(lost[i], host.dissipated_energy, 1e-14 * (std::abs(host.dissipated_energy) + 1e-300)) << "pair " << i;
  }
}

// One SRD step of 4096 particles in an 8^3 box, periodic and between walls
// under gravity: the cell matrices (random axis, rotation, granular factor)
// to 1e-14, the cells identical, positions and velocities to 1e-12 (the
// device may fuse multiply-adds, a few ulp per operation).
TEST(HostDevice, SrdStepAgrees) {
  if (const std::string why = no_device(); !why.empty()) GTEST_SKIP() << why;
  for (int walls : {0, 1}) {
    SrdCheckInput in{{8, 8, 8}, {0.21, -0.37, 0.44}, 0.3, std::cos(2.2), std::sin(2.2), 0.97, -0.5, 123, 45, walls};
    const int cell_count = 8 * 8 * (8 + (walls ? 2 : 0)), count = 4096;
    std::vector<double> device_matrices(9 * cell_count), host_matrices(9 * cell_count), means(3 * cell_count);
    srd_cell_matrices_on_device(in, cell_count, device_matrices.data());
    for (int c = 0; c < cell_count; ++c) {
      srd::check_cell_matrix(in, static_cast<std::uint64_t>(c), host_matrices.data() + 9 * c);
      for (int a = 0; a < 3; ++a) means[3 * c + a] = 0.1 * std::sin(c + a);
    }
    for (int k = 0; k < 9 * cell_count; ++k) ASSERT_NEAR(device_matrices[k], host_matrices[k], 1e-14) << "entry " << k;
    std::vector<double> x(3 * count), v(3 * count);
    for (int i = 0; i < count; ++i) {
      Philox random(stream::srd_initial, 9, 0, static_cast<std::uint64_t>(i));
      for (int a = 0; a < 3; ++a) x[3 * i + a] = 8.0 * random.uniform();
      for (int a = 0; a < 3; ++a) v[3 * i + a] = random.normal();
    }
    std::vector<double> xd = x, vd = v;
    std::vector<std::uint32_t> device_cell(count);
    srd_particles_on_device(in, count, host_matrices.data(), means.data(), xd.data(), vd.data(), device_cell.data());
    for (int i = 0; i < count; ++i) {
      const std::uint32_t c = srd::check_particle_step(in, host_matrices.data(), means.data(), &x[3 * i], &v[3 * i]);
      ASSERT_EQ(device_cell[i], c) << "particle " << i;
      for (int a = 0; a < 3; ++a) {
        ASSERT_NEAR(xd[3 * i + a], x[3 * i + a], 1e-12) << "particle " << i;
        ASSERT_NEAR(vd[3 * i + a], v[3 * i + a], 1e-12) << "particle " << i;
      }
    }
  }
}

}  // namespace
}  // namespace granflow::cuda
