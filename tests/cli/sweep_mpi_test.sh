#!/usr/bin/env bash
# granflow sweep over MPI ranks (a -DGRANFLOW_MPI=ON build): two ranks give
# the summary and the observables of a one-worker sweep; a sweep whose rank
# is killed mid-way is finished by the same command; shards run under
# mpirun and --collect agree with it too; errors are reported once, with
# exit status 2, and rank 0 alone reports the sweep; `granflow run` of a
# scenario without a distributed step (haff_cooling), started as several
# ranks, is refused once, with exit status 2, and writes nothing.
set -u
granflow="$1"
mpiexec="$2"
scenario="$3"
source "$(dirname "$0")/common.sh"
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# Open MPI refuses root unless told; CI runs as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ranks() { local n="$1"; shift; "$mpiexec" -np "$n" --oversubscribe "$granflow" "$@"; }

source "$(dirname "$0")/cooling_sweep.sh"
write_cooling_sweep "$work/sweep.toml" "$scenario"

same_tables() {  # same_tables DIR what
  for table in summary.csv summary_runs.csv; do
    if cmp -s "$work/local/$table" "$1/$table"; then echo "ok: $table identical ($2)"
    else fail "$table differs ($2)"; diff "$work/local/$table" "$1/$table"; fi
  done
}

output=$(ranks 2 run "$scenario" -q --set system.count=200 --set run.t_stop=1 -o "$work/one_system.h5md" 2>&1); status=$?
refusals=$(grep -c "has no distributed step" <<< "$output")
if [[ $status -ne 0 && $refusals -eq 1 && ! -e "$work/one_system.h5md" && ! -e "$work/one_system.h5md.partial" ]]; then
  echo "ok: granflow run under 2 ranks refused once, nothing written"
else
  fail "granflow run under 2 ranks: exit $status, $refusals refusals, files: $(ls "$work" | grep one_system): $output"
fi

"$granflow" sweep "$work/sweep.toml" -j 1 -o "$work/local" -q || fail "one-machine sweep exited with $?"
output=$(ranks 2 sweep "$work/sweep.toml" -j 1 -o "$work/ranks" 2>&1); status=$?
[[ $status -eq 0 ]] || fail "2-rank sweep exited with $status: $output"
same_tables "$work/ranks" "2 ranks against 1 worker"
starts=$(grep -c "2 ranks with 2 workers in all" <<< "$output")
[[ $starts -eq 1 ]] && echo "ok: rank 0 alone announces the sweep" || fail "sweep announced $starts times: $output"
# The runs themselves, not only their last values: every observable series
# of every result file equal to the one-machine sweep's.
if /usr/bin/python3 - "$work/local" "$work/ranks" <<'PY'
import sys, glob, os, h5py, numpy as np
local, ranks = sys.argv[1:]
files = sorted(glob.glob(os.path.join(local, "p*_r*.h5md")))
assert len(files) == 8, files
for path in files:
    with h5py.File(path) as a, h5py.File(os.path.join(ranks, os.path.basename(path))) as b:
        names = []
        a["observables"].visit(lambda n: names.append(n) if isinstance(a["observables"][n], h5py.Dataset) else None)
        assert names, path
        for n in names:
            if not np.array_equal(a["observables"][n][()], b["observables"][n][()]):
                sys.exit(f"{os.path.basename(path)}: /observables/{n} differs")
PY
then echo "ok: every observable of the 8 runs identical"; else fail "result files differ between 2 ranks and 1 worker"; fi

# Kill one rank once two runs are complete: mpirun ends the job; the same
# command finishes it, with the tables of an uninterrupted one-worker run.
# The elastic point, whose runs take longest (an inelastic gas cools and
# slows), goes last, so that the kill lands while its runs go on.
sed 's/collision.restitution = \[1.0, 0.9, 0.8, 0.6\]/collision.restitution = [0.6, 0.8, 0.9, 1.0]/' "$work/sweep.toml" \
  > "$work/reordered.toml"
grep -q "0.6, 0.8, 0.9, 1.0" "$work/reordered.toml" || fail "the sweep to kill was not reordered"
"$granflow" sweep "$work/reordered.toml" -j 1 -o "$work/reordered_local" -q || fail "one-machine reordered sweep exited with $?"
ranks 2 sweep "$work/reordered.toml" -j 1 -o "$work/killed" -q > "$work/killed.log" 2>&1 &
launcher=$!
for _ in $(seq 1 3000); do
  [[ $(ls "$work/killed"/p*_r*.h5md 2>/dev/null | wc -l) -ge 2 ]] && break
  sleep 0.02
done
# A rank (its command line starts with granflow's path), never the launcher.
victim=$(pgrep -n -f "^$granflow sweep $work/reordered.toml -j 1 -o $work/killed")
[[ -n "$victim" ]] && kill -9 "$victim"
wait "$launcher"; status=$?
left=$(ls "$work/killed"/p*_r*.h5md 2>/dev/null | wc -l)
echo "rank killed with $left of 8 runs complete (mpirun exit $status)"
[[ $status -ne 0 && $left -lt 8 ]] || fail "the sweep finished before a rank could be killed (exit $status, $left runs)"
ranks 2 sweep "$work/reordered.toml" -j 1 -o "$work/killed" -q || fail "rerun after the killed rank exited with $?"
for table in summary.csv summary_runs.csv; do
  if cmp -s "$work/reordered_local/$table" "$work/killed/$table"; then echo "ok: $table identical (after a killed rank and a rerun)"
  else fail "$table differs (after a killed rank and a rerun)"; fi
done
ls "$work/killed"/*.partial >/dev/null 2>&1 && fail "partial files left after the rerun"

# Shards of a job array can themselves be MPI jobs.
ranks 2 sweep "$work/sweep.toml" -j 1 -o "$work/shards" -q --shard 1/2 || fail "shard 1/2 on 2 ranks exited with $?"
"$granflow" sweep "$work/sweep.toml" -j 1 -o "$work/shards" -q --shard 2/2 || fail "shard 2/2 exited with $?"
ranks 2 sweep "$work/sweep.toml" -o "$work/shards" -q --collect || fail "--collect on 2 ranks exited with $?"
same_tables "$work/shards" "shard 1/2 on 2 ranks, 2/2 on one, collected on 2 ranks"

# Errors: reported once, exit status 2.
sed 's/"temperature", //; s/summary = \[/summary = ["temperatur", /' "$work/sweep.toml" > "$work/misspelt.toml"
output=$(ranks 2 sweep "$work/misspelt.toml" -j 1 -o "$work/misspelt" -q 2>&1); status=$?
count=$(grep -c "summary observable 'temperatur'" <<< "$output")
[[ $status -eq 2 && $count -eq 1 ]] && echo "ok: a misspelt summary name stops every rank, reported once" \
  || fail "misspelt summary on 2 ranks: exit $status, reported $count times: $output"
[[ $(ls "$work/misspelt"/p*_r*.h5md 2>/dev/null | wc -l) -le 2 ]] \
  && echo "ok: no new run started after the misspelt name was found" || fail "runs went on after the misspelt name"
output=$(ranks 2 sweep "$work/nonexistent.toml" -q 2>&1); status=$?
count=$(grep -c "cannot read sweep file" <<< "$output")
[[ $status -eq 2 && $count -eq 1 ]] && echo "ok: a missing sweep file reported once" \
  || fail "missing sweep file on 2 ranks: exit $status, reported $count times: $output"
sed 's/"run.t_stop" = 30.0/"run.t_stop" = 20.0/' "$work/sweep.toml" > "$work/stale.toml"
output=$(ranks 2 sweep "$work/stale.toml" -o "$work/ranks" -q 2>&1); status=$?
[[ $status -eq 2 && "$output" == *"different configuration"* ]] && echo "ok: stale result directory refused" \
  || fail "stale result directory on 2 ranks: exit $status: $output"

[[ $failures -eq 0 ]] && echo "all MPI sweep checks passed" || echo "$failures MPI sweep checks failed"
exit $((failures > 0))
