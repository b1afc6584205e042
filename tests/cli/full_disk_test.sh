#!/usr/bin/env bash
# Writing on a full file system (here: a file-size limit, SIGXFSZ ignored so
# writes fail as on a full disk) ends in a clear error and exit status 1 for
# a run and 3 for a sweep (every run failed), never in a crash, and leaves no
# half-written file under a final name.
set -u
granflow="$1"
scenarios="$2"
source "$(dirname "$0")/common.sh"
args=(--set system.count=3000 --set system.radius=0.01 --set run.t_stop=5 --set output.positions=all -q)

status=0
(trap '' XFSZ; ulimit -f 100; exec "$granflow" run "$scenarios/haff_cooling.toml" "${args[@]}" -o "$work/run.h5") \
  2> "$work/run.log" || status=$?
if [[ $status -ne 1 ]] || ! grep -q "HDF5 error: append to" "$work/run.log"; then
  echo "FAIL: run on a full disk exited $status:"; cat "$work/run.log"; failures=$((failures + 1))
else
  echo "ok: run on a full disk: $(tail -1 "$work/run.log")"
fi
[[ -e "$work/run.h5" || -e "$work/run.h5.partial" ]] && { echo "FAIL: a file was left behind"; failures=$((failures + 1)); }

cp "$scenarios/haff_cooling.toml" "$work/"
cat > "$work/sweep.toml" <<TOML
scenario_file = "haff_cooling.toml"
output = "$work/sweep"
[set]
"system.count" = 3000
"system.radius" = 0.01
"run.t_stop" = 5.0
"output.positions" = "all"
[grid]
"collision.restitution" = [0.8, 0.9]
TOML
status=0
(trap '' XFSZ; ulimit -f 100; exec "$granflow" sweep "$work/sweep.toml" -j 2 -q) 2> "$work/sweep.log" || status=$?
if [[ $status -ne 3 ]] || ! grep -q "HDF5 error: append to" "$work/sweep.log"; then
  echo "FAIL: sweep on a full disk exited $status (expected 3, every run failed, naming the write):"
  cat "$work/sweep.log"; failures=$((failures + 1))
else
  echo "ok: sweep on a full disk exited $status"
fi
echo "$failures failure(s)"
[[ $failures -eq 0 ]]
