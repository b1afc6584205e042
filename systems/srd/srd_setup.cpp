#include "systems/srd/srd_setup.hpp"

namespace granflow::srd {

void declare_srd_keys(ConfigSchema& s, const SrdDefaults& d) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  s.integer("system.dimension", d.dimension, 2, 3, "2 or 3 dimensions")
      .real_array("system.cells", d.cells, 2, 1e6, 2, 3, "cells per axis (one entry per dimension); lengths are in cell sizes a")
      .integer("srd.particles_per_cell", d.particles_per_cell, 1, 100000, "mean particles per cell n0")
      .real("srd.rotation_angle", d.angle, 0.0, 180.0, "rotation angle alpha in degrees")
      .real("srd.time_step", d.dt, 0.0, inf, "time step dt between collisions", true)
      .real("srd.temperature", d.temperature, 0.0, inf, "initial temperature kT (particle mass 1)", true)
      .real("srd.restitution", d.restitution, 0.0, 1.0, "restitution eps of granular SRD; 1: standard SRD")
      .real("srd.diameter", d.diameter, 0.0, inf, "particle diameter sigma in the effective restitution, in cell sizes")
      .boolean("srd.grid_shift", true, "shift the grid at random every step (Galilean invariance)")
      .choice("srd.dissipation", "rotated_plane", {"rotated_plane", "random_axis", "whole"},
              "granular rule: scale the rotated thermal components (the rotation's plane; all in 2D), only along a "
              "random axis, or the whole rotated velocity")
      .integer("srd.reorder_interval", 0, 0, 1000000000,
               "steps between putting particles in cell order (0: from the mean free path, 2 / (sqrt(kT) dt) "
               "between 5 and 100)")
      .real("shear.rate", d.shear_rate, 0.0, inf, "shear rate du_x/dy through Lees-Edwards planes along y (0: none)")
      .real("thermostat.temperature", d.thermostat, 0.0, inf, "target temperature of the global thermostat (0: none)")
      .choice("srd.device", "cpu", {"cpu", "cuda", "thrust_host"},
              "where the step runs: cpu (the CPU systems, every core), cuda (the device step on an NVIDIA GPU; a "
              "build with GRANFLOW_CUDA=ON and a CUDA driver) or thrust_host (the device step's source on Thrust's "
              "oneTBB back end: a build without CUDA, with Thrust's headers)")
      .integer("run.steps", d.steps, 1, 1000000000000, "collision steps to run")
      .integer("fields.every_steps", 0, 0, 1000000000000,
               "steps between density, velocity and temperature fields to /fields (0: none)")
      .integer("fields.window", 10, 1, 1000000000000, "steps averaged into each field output")
      .real("balance.cell_weight", 8.0, 0.0, inf,
            "over MPI ranks: a cell's share of a slab's load, in particles (its rotation and reduction against a "
            "particle's whole step; 8 measured at n0 = 10 in 3D)");
  // A finished run (output.final_checkpoint) extends with --resume --set run.steps=...
  s.allow_change_on_resume("run.steps");
  s.unit("srd.time_step", unit::time)
      .unit("srd.temperature", unit::energy)
      .unit("srd.diameter", unit::length)
      .unit("srd.rotation_angle", "deg")
      .unit("system.cells", unit::none)
      .unit("shear.rate", unit::rate)
      .unit("thermostat.temperature", unit::energy)
      .unit("srd.restitution", unit::none)
      .unit("balance.cell_weight", unit::none);
  declare_slab_balance_keys(s, 500, 1.1, "its slab's particles and cells");
  declare_stored_start_keys(s);
}

void declare_srd_wall_keys(ConfigSchema& s) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  ConfigSchema wall;
  wall.choice("axis", "y", {"x", "y", "z"}, "the axis the wall is perpendicular to")
      .choice("side", "lower", {"lower", "upper"}, "lower: at 0, the fluid above it; upper: at the box length, below it")
      .choice("kind", "no_slip", {"no_slip", "slip"},
              "no_slip: bounce-back, cut cells filled with ghost particles; slip: specular reflection")
      .real("temperature", 0.0, 0.0, inf, "temperature of its ghost particles (0: srd.temperature)")
      .boolean("ghosts", true, "no_slip only: fill the cells it cuts with ghost particles (false: plain bounce-back)")
      .real("amplitude", 0.0, 0.0, inf, "amplitude A of its motion A sin(2 pi f t) along its normal")
      .real("frequency", 0.0, 0.0, inf, "frequency f of that motion");
  wall.unit("temperature", unit::energy).unit("amplitude", unit::length).unit("frequency", unit::rate);
  s.table_array("walls", std::move(wall), 0, 6, "walls replacing the periodic boundary of an axis, both sides of it")
      .real_array("force.acceleration", {}, -1e300, 1e300, 0, 3,
                  "constant body force per mass (gravity), one entry per dimension; empty: none")
      .real_array("force.slab", {}, -1e300, 1e300, 0, 2,
                  "[from, to]: the force acts only on particles with from <= coordinate < to along force.slab_axis "
                  "at the start of a step; empty: everywhere")
      .choice("force.slab_axis", "y", {"x", "y", "z"}, "the axis force.slab is measured along");
  s.unit("force.acceleration", unit::acceleration).unit("force.slab", unit::length);
}


template void add_srd_fluid<2>(Run&, std::vector<Wall>, BodyForce<2>, bool);
template void add_srd_fluid<3>(Run&, std::vector<Wall>, BodyForce<3>, bool);

}  // namespace granflow::srd
