#!/usr/bin/env bash
# A run can be watched while it runs: its OUTPUT.partial opens in h5py (the
# run's lock is not the flock HDF5 readers take, and the file is flushed
# about once a second), and the series read from it grow from one read to
# the next. --log N prints a table of observables every N outputs, and names
# an observable the run does not record.
#   watch_test.sh GRANFLOW HAFF_COOLING_TOML
set -u
granflow="$1"
scenario="$2"
source "$(dirname "$0")/common.sh"
"$granflow" run "$scenario" --set system.count=20000 --set system.radius=0.005 --set collision.restitution=1 \
  --set run.t_stop=60 --set output.points_per_decade=40 -q -o "$work/watch.h5md" &
run=$!
/usr/bin/python3 - "$work/watch.h5md" "$run" <<'PY' || failures=$((failures + 1))
import os, sys, time
import h5py
path, pid = sys.argv[1], int(sys.argv[2])
lengths, errors = [], 0
def running():
    try:
        os.kill(pid, 0)
        return not os.path.exists(path)
    except OSError:
        return False
while running():
    time.sleep(0.5)
    try:
        with h5py.File(path + ".partial", "r") as f:
            lengths.append(len(f["/observables/temperature/time"]))
    except (OSError, KeyError) as error:
        errors += 1  # between two flushes, or before the first output
grew = sum(1 for a, b in zip(lengths, lengths[1:]) if b > a)
print(f"{len(lengths)} reads of the running file ({errors} failed), series lengths {lengths}")
if grew < 2 or any(b < a for a, b in zip(lengths, lengths[1:])):
    sys.exit("FAIL: the series read from OUTPUT.partial did not grow while the run went on")
print("ok: the running file reads, and its series grow")
PY
wait "$run" || { echo "FAIL: the watched run exited $?"; failures=$((failures + 1)); }

log=$("$granflow" run "$scenario" --set run.t_stop=2 --log 2 --log-observables temperature,kinetic_energy \
  -o "$work/log.h5md" 2>&1)
rows=$(grep -cE "^ +[0-9]+ +[0-9.e+-]+ +[0-9.e+-]+ +[0-9.e+-]+$" <<< "$log")
[[ "$log" == *"temperature"*"kinetic_energy"* && $rows -ge 5 ]] && echo "ok: --log 2 printed $rows rows" \
  || { echo "FAIL: --log: $log"; failures=$((failures + 1)); }
output=$("$granflow" run "$scenario" --set run.t_stop=2 --log 1 --log-observables temprature -o "$work/x.h5md" 2>&1)
status=$?
[[ $status -eq 2 && "$output" == *"did you mean 'temperature'"* ]] && echo "ok: --log-observables with a misspelt name" \
  || { echo "FAIL: --log-observables temprature: exit $status: $output"; failures=$((failures + 1)); }
echo "$failures failure(s)"
[[ $failures -eq 0 ]]
