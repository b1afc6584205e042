# Sourced by the sweep tests: write_cooling_sweep FILE SCENARIO writes a
# sweep of 4 restitutions x 2 repeats of a small cooling gas (~0.5 s per run).
write_cooling_sweep() {
  cat > "$1" <<TOML
scenario_file = "$2"
output = "unused"
repeats = 2
summary = ["temperature", "collisions_per_particle", "pair_collisions"]
[set]
"system.count" = 2000
"run.t_stop" = 30.0
"output.positions" = "none"
[grid]
collision.restitution = [1.0, 0.9, 0.8, 0.6]
TOML
}
