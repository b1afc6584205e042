#!/usr/bin/env bash
# granflow sweep: the same sweep with 1 and 2 workers gives identical
# summaries; a sweep killed with SIGKILL and run again finishes the missing
# points and gives the same summary as an uninterrupted one; one stopped
# with SIGINT checkpoints its runs and continues them bit for bit; three shards
# and --collect give the same summary, and a missing shard is named; bad
# sweep files exit with status 2 and a message naming the problem; a build
# without MPI started as MPI ranks refuses to run.
set -u
granflow="$1"
scenario="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

source "$(dirname "$0")/cooling_sweep.sh"
write_cooling_sweep "$work/sweep.toml" "$scenario"

"$granflow" sweep "$work/sweep.toml" -j 1 -o "$work/one" -q || fail "sweep with 1 worker exited with $?"
"$granflow" sweep "$work/sweep.toml" -j 2 -o "$work/two" -q || fail "sweep with 2 workers exited with $?"
for table in summary.csv summary_runs.csv; do
  if cmp -s "$work/one/$table" "$work/two/$table"; then echo "ok: $table identical for 1 and 2 workers"
  else fail "$table differs between 1 and 2 workers"; diff "$work/one/$table" "$work/two/$table"; fi
done
rows=$(($(wc -l < "$work/one/summary.csv") - 1))
[[ $rows -eq 4 ]] && echo "ok: 4 parameter points" || fail "summary has $rows points, expected 4"
runs=$(($(wc -l < "$work/one/summary_runs.csv") - 1))
[[ $runs -eq 8 ]] && echo "ok: 8 runs" || fail "summary_runs has $runs runs, expected 8"
grep -q '^point,runs,collision.restitution,temperature_mean,temperature_stderr' "$work/one/summary.csv" \
  && echo "ok: summary header" || fail "summary header: $(head -1 "$work/one/summary.csv")"

# Kill once at least two runs are complete, then resume. The elastic
# point, whose runs take longest (an inelastic gas cools and slows), goes
# last, so that the kill lands while its runs go on even on a loaded machine.
sed 's/collision.restitution = \[1.0, 0.9, 0.8, 0.6\]/collision.restitution = [0.6, 0.8, 0.9, 1.0]/' "$work/sweep.toml" \
  > "$work/reordered.toml"
grep -q "0.6, 0.8, 0.9, 1.0" "$work/reordered.toml" || fail "the sweep to kill was not reordered"
"$granflow" sweep "$work/reordered.toml" -j 2 -o "$work/reordered" -q || fail "reordered sweep exited with $?"
"$granflow" sweep "$work/reordered.toml" -j 2 -o "$work/killed" -q &
pid=$!
for _ in $(seq 1 600); do
  done_runs=$(ls "$work/killed"/p*_r*.h5md 2>/dev/null | wc -l)
  [[ $done_runs -ge 2 ]] && break
  sleep 0.02
done
kill -9 "$pid" 2>/dev/null; wait "$pid" 2>/dev/null
left=$(ls "$work/killed"/p*_r*.h5md 2>/dev/null | wc -l)
echo "killed with $left of 8 runs complete"
[[ $left -lt 8 ]] || fail "the sweep finished before it could be killed; the resume path was not exercised"
"$granflow" sweep "$work/reordered.toml" -j 2 -o "$work/killed" -q || fail "resumed sweep exited with $?"
if cmp -s "$work/reordered/summary.csv" "$work/killed/summary.csv"; then echo "ok: resumed summary identical"
else fail "resumed summary differs"; diff "$work/reordered/summary.csv" "$work/killed/summary.csv"; fi
ls "$work/killed"/*.partial >/dev/null 2>&1 && fail "partial files left after the resumed sweep"

# SIGINT stops the runs under way at a safe point (each checkpoints), exits
# 130 and starts no more; the same command continues them: the summary and
# every result equal an uninterrupted sweep's.
cat > "$work/beds.toml" <<TOML
scenario_file = "$(dirname "$scenario")/shaken_bed.toml"
summary = ["asymmetry_abs_mean", "crossings"]
[set]
"run.t_stop" = 25.0
"output.average_after" = 5.0
[grid]
shaking.amplitude = [0.6, 1.2]
TOML
"$granflow" sweep "$work/beds.toml" -j 2 -o "$work/beds" -q || fail "bed sweep exited with $?"
"$granflow" sweep "$work/beds.toml" -j 2 -o "$work/beds_cut" -q 2> "$work/beds_cut.log" &
pid=$!
# Interrupted once its runs are under way (a run's output exists), however
# loaded the machine is.
for _ in $(seq 1 500); do
  ls "$work/beds_cut"/*.partial >/dev/null 2>&1 && break
  sleep 0.02
done
sleep 0.5
kill -INT "$pid"; wait "$pid"; status=$?
checkpoints=$(ls "$work/beds_cut"/*.checkpoint 2>/dev/null | wc -l)
if [[ $status -eq 130 && $checkpoints -ge 1 ]] && grep -q "run the same command to continue" "$work/beds_cut.log"; then
  echo "ok: SIGINT stopped the sweep with $checkpoints run(s) checkpointed"
else fail "SIGINT to a sweep: exit $status, $checkpoints checkpoints: $(cat "$work/beds_cut.log")"; fi
"$granflow" sweep "$work/beds.toml" -j 2 -o "$work/beds_cut" -q || fail "continued bed sweep exited with $?"
if cmp -s "$work/beds/summary_runs.csv" "$work/beds_cut/summary_runs.csv"; then echo "ok: continued sweep identical"
else fail "continued sweep differs"; diff "$work/beds/summary_runs.csv" "$work/beds_cut/summary_runs.csv"; fi
ls "$work/beds_cut"/*.checkpoint >/dev/null 2>&1 && fail "checkpoints left after the continued sweep"

# Shards for job arrays: 1/3, 2/3 and 3/3, then --collect, give the summary
# of the one-machine sweep; before shard 2 has run, --collect names it and
# its runs.
for shard in 1 3; do
  "$granflow" sweep "$work/sweep.toml" -j 2 -o "$work/shards" -q --shard "$shard/3" \
    || fail "shard $shard/3 exited with $?"
done
output=$("$granflow" sweep "$work/sweep.toml" -o "$work/shards" --collect 2>&1); status=$?
[[ $status -eq 3 && "$output" == *"shard 2/3 has not finished (no shard_2_of_3.txt)"* && "$output" == *".h5md"* ]] \
  && echo "ok: --collect names the missing shard and its runs" \
  || fail "--collect with shard 2/3 missing: exit $status: $output"
"$granflow" sweep "$work/sweep.toml" -j 2 -o "$work/shards" -q --shard 2/3 || fail "shard 2/3 exited with $?"
"$granflow" sweep "$work/sweep.toml" -o "$work/shards" -q --collect || fail "--collect exited with $?"
for table in summary.csv summary_runs.csv; do
  if cmp -s "$work/one/$table" "$work/shards/$table"; then echo "ok: $table of three shards identical"
  else fail "$table differs between one machine and three shards"; diff "$work/one/$table" "$work/shards/$table"; fi
done
listed=$(cat "$work/shards"/shard_*_of_3.txt | awk '{print $1}' | sort -u | wc -l)
lines=$(cat "$work/shards"/shard_*_of_3.txt | wc -l)
[[ $listed -eq 8 && $lines -eq 8 ]] && echo "ok: each of the 8 runs in exactly one shard" \
  || fail "shard records list $lines runs, $listed distinct, expected 8"
output=$("$granflow" sweep "$work/sweep.toml" -o "$work/shards" -q --shard 4/3 2>&1); status=$?
[[ $status -eq 2 && "$output" == *"--shard '4/3'"* ]] && echo "ok: --shard 4/3 refused" \
  || fail "--shard 4/3: exit $status: $output"

expect_error() {  # expect_error "needle" sweep-file-text
  local needle="$1" text="$2" output status
  printf '%s\n' "$text" > "$work/bad.toml"
  output=$("$granflow" sweep "$work/bad.toml" -o "$work/bad" -q 2>&1); status=$?
  if [[ $status -ne 2 ]]; then fail "sweep exited with $status, expected 2: $text"; echo "$output"
  elif [[ "$output" != *"$needle"* ]]; then fail "message lacks '$needle': $output"
  else echo "ok: $needle"; fi
}
expect_error "unknown key 'repeat'" "scenario_file = \"$scenario\"
repeat = 3"
expect_error "needs scenario_file" "repeats = 3"
expect_error "'collision.restitution' = 1.5 is out of range" "scenario_file = \"$scenario\"
[grid]
collision.restitution = [0.5, 1.5]"
expect_error "unknown configuration key 'collision.restitutoin'" "scenario_file = \"$scenario\"
[grid]
collision.restitutoin = [0.5]"
expect_error "[zip] lists must have equal lengths" "scenario_file = \"$scenario\"
[zip]
collision.restitution = [0.5, 0.6]
system.count = [100]"
expect_error "parameter point 1: unknown configuration key 'collision.restitutoin'" "scenario_file = \"$scenario\"
[[points]]
collision.restitution = 0.5
[[points]]
collision.restitutoin = 0.6"
expect_error "'collision.restitution' is swept in both [grid] and [zip]" "scenario_file = \"$scenario\"
[grid]
collision.restitution = [0.5, 0.6]
[zip]
collision.restitution = [0.7]"
expect_error "repeats = 0 is out of range" "scenario_file = \"$scenario\"
repeats = 0"
expect_error "must be a non-empty array" "scenario_file = \"$scenario\"
[grid]
collision.restitution = 0.5"
expect_error "cost key 'system.cuont' is not a configuration key" "scenario_file = \"$scenario\"
cost = [\"system.cuont\"]"
expect_error "cost must be an array of configuration keys" "scenario_file = \"$scenario\"
cost = \"system.count\""
# A misspelt summary name stops the sweep after its first run, naming the
# name and the scalar observables there are.
cat > "$work/misspelt.toml" <<TOML
scenario_file = "$scenario"
summary = ["temperatur"]
[set]
"system.count" = 500
"run.t_stop" = 5.0
"output.positions" = "none"
[grid]
collision.restitution = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5]
TOML
output=$("$granflow" sweep "$work/misspelt.toml" -j 1 -o "$work/misspelt" -q 2>&1); status=$?
results=$(ls "$work/misspelt"/*.h5md 2>/dev/null | wc -l)
if [[ $status -eq 2 && "$output" == *"summary observable 'temperatur'"* && "$output" == *"temperature"* \
      && $results -eq 1 ]]; then echo "ok: misspelt summary name stops the sweep after one run"
else fail "misspelt summary name: exit $status, $results result files: $output"; fi
# Rerun with the name fixed: the first run is reused, so the check comes before any new run.
sed -i 's/"temperatur"/"temperature", "nonexistent"/' "$work/misspelt.toml"
output=$("$granflow" sweep "$work/misspelt.toml" -j 1 -o "$work/misspelt" -q 2>&1); status=$?
results=$(ls "$work/misspelt"/*.h5md 2>/dev/null | wc -l)
[[ $status -eq 2 && "$output" == *"'nonexistent'"* && $results -eq 1 ]] \
  && echo "ok: summary names checked against a reused result before any run" \
  || fail "reused-result summary check: exit $status, $results result files: $output"

# A result directory written with other settings is not silently mixed in.
sed -i 's/"run.t_stop" = 30.0/"run.t_stop" = 20.0/' "$work/sweep.toml"
output=$("$granflow" sweep "$work/sweep.toml" -o "$work/one" -q 2>&1); status=$?
[[ $status -eq 2 && "$output" == *"different configuration"* ]] && echo "ok: stale result directory refused" \
  || fail "stale result directory: exit $status: $output"

# Without MPI, a sweep started as several ranks would run once per rank into
# the same directory: refused, naming the build option (an MPI build is
# checked under mpirun by sweep_mpi_test.sh).
if "$granflow" --version | grep -q "GRANFLOW_MPI=OFF"; then
  output=$(OMPI_COMM_WORLD_SIZE=2 "$granflow" sweep "$work/sweep.toml" -o "$work/ranks" -q 2>&1); status=$?
  [[ $status -eq 2 && "$output" == *"-DGRANFLOW_MPI=ON"* && ! -e "$work/ranks" ]] \
    && echo "ok: a build without MPI refuses to run as MPI ranks" || fail "sweep as 2 ranks without MPI: exit $status: $output"
fi

[[ $failures -eq 0 ]] && echo "all sweep checks passed" || echo "$failures sweep checks failed"
exit $((failures > 0))
