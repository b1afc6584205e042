# What the tests of one system over MPI ranks share, sourced with the
# test's arguments: the granflow program, mpiexec and the scenarios folder.
granflow="$1"
mpiexec="$2"
scenarios="$3"
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# ranks K ARGS...: granflow on K ranks, oversubscribed on a small machine.
ranks() { local n="$1"; shift; "$mpiexec" -np "$n" --oversubscribe --bind-to none "$granflow" "$@"; }

# refused PATTERN K ARGS...: the run on K ranks is refused, said once (rank
# 0), and leaves no result file.
refused() {  # refused PATTERN RANKS ARGS...
  local pattern="$1"; shift
  local output status
  output=$(ranks "$@" -q -o "$work/refused.h5" 2>&1); status=$?
  local said; said=$(grep -c "$pattern" <<< "$output")
  if [[ $status -ne 0 && $said -eq 1 && ! -e "$work/refused.h5" ]]; then echo "ok: refused once: $pattern"
  else fail "expected one refusal '$pattern' (exit $status, said $said times): $output"; fi
}

# agree A B TOLERANCE [SKIPPED...]: every dataset but provenance, timings and
# those under SKIPPED, floats within TOLERANCE of the dataset's largest
# magnitude (0: bit for bit), others equal.
agree() {
  /usr/bin/python3 - "$@" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
tolerance = float(sys.argv[3])
skipped = tuple(sys.argv[4:])  # path prefixes left out
paths, worst = [], 0.0
a.visititems(lambda n, o: paths.append(n) if isinstance(o, h5py.Dataset) and not n.startswith(("provenance", "profile") + skipped) else None)
for path in paths:
    if path not in b: sys.exit(f"FAIL: {sys.argv[2]} lacks {path}")
    x, y = np.asarray(a[path][()]), np.asarray(b[path][()])
    if x.shape != y.shape: sys.exit(f"FAIL: {path}: shapes {x.shape} and {y.shape}")
    if tolerance > 0 and np.issubdtype(x.dtype, np.floating):
        scale = np.nanmax(np.abs(x)) if x.size and not np.all(np.isnan(x)) else 0.0
        gap = np.nanmax(np.abs(x - y)) if x.size and not np.all(np.isnan(x)) else 0.0
        if not np.array_equal(np.isnan(x), np.isnan(y)) or gap > tolerance * max(scale, 1e-300):
            sys.exit(f"FAIL: {path} differs by {gap:.3g} (largest value {scale:.3g}) between {sys.argv[1]} and {sys.argv[2]}")
        if scale > 0: worst = max(worst, gap / scale)
    elif not np.array_equal(x, y, equal_nan=np.issubdtype(x.dtype, np.floating)):
        sys.exit(f"FAIL: {path} differs between {sys.argv[1]} and {sys.argv[2]}")
print(f"ok: {sys.argv[2]} agrees with {sys.argv[1]} in {len(paths)} datasets "
      + (f"(largest relative difference {worst:.2g})" if tolerance > 0 else "(bit for bit)"))
PY
}

# interrupted K OUT ARGS...: `granflow ARGS -o OUT` on K ranks, SIGINT to the
# launcher half a second into the stepping: every rank stops at one step, rank 0
# writes the checkpoint and says so once, and no result file is left. The
# launcher starts with SIGINT handled as from a terminal: a script's
# background job inherits it ignored (or blocked), and mpirun keeps it so.
interrupted() {
  local k="$1" out="$2"; shift 2
  /usr/bin/python3 -c 'import os, signal, sys
signal.signal(signal.SIGINT, signal.SIG_DFL)
signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
os.execvp(sys.argv[1], sys.argv[1:])' \
    "$mpiexec" -np "$k" --oversubscribe --bind-to none "$granflow" "$@" --log 1 -o "$out" > "$out.log" 2>&1 &
  local launcher=$!
  after_stepping_starts "$out.log" 0.5 "$launcher"
  kill -INT "$launcher"
  wait "$launcher"; local status=$?
  if [[ $status -ne 0 && -e "$out.checkpoint" && ! -e "$out" && ! -e "$out.partial" ]] \
     && [[ $(grep -c "interrupted (signal" "$out.log") -eq 1 ]]; then
    echo "ok: SIGINT stopped the $k ranks with one checkpoint and one message (mpirun exit $status)"
  else
    fail "SIGINT: exit $status, files: $(ls "$(dirname "$out")" | tr '\n' ' '), log: $(cat "$out.log")"
  fi
}

# killed K OUT ARGS...: `granflow ARGS -o OUT` on K ranks (ARGS with a
# periodic checkpoint), one rank killed outright once the first checkpoint
# is written: the job ends with a failure and leaves the checkpoint.
killed() {
  local k="$1" out="$2"; shift 2
  ranks "$k" "$@" -o "$out" > "$out.log" 2>&1 &
  local launcher=$!
  for _ in $(seq 1 1500); do [[ -e "$out.checkpoint" ]] && break; sleep 0.02; done
  local victim; victim=$(pgrep -n -f "^$granflow .*-o $out")
  [[ -n "$victim" ]] && kill -9 "$victim"
  wait "$launcher"; local status=$?
  if [[ $status -ne 0 && -e "$out.checkpoint" && -n "$victim" ]]; then echo "ok: a killed rank ended the job (mpirun exit $status)"
  else fail "killed rank: exit $status, victim '${victim}', files: $(ls "$(dirname "$out")" | tr '\n' ' ')"; fi
}

# terminated K OUT ARGS...: `granflow ARGS -o OUT` on K ranks, SIGTERM to
# the last rank alone (as a scheduler may signal one process): every rank
# stops at one step, rank 0 writes the checkpoint and says which signal
# once, the job exits with 128 + 15, and no result file is left.
terminated() {
  local k="$1" out="$2"; shift 2
  ranks "$k" "$@" --log 1 -o "$out" > "$out.log" 2>&1 &
  local launcher=$!
  after_stepping_starts "$out.log" 0.5 "$launcher"
  local victim="" pid
  for pid in $(pgrep -f "^$granflow .*-o $out"); do
    grep -qxz "OMPI_COMM_WORLD_RANK=$((k - 1))" "/proc/$pid/environ" 2>/dev/null && victim=$pid
  done
  [[ -n "$victim" ]] && kill -TERM "$victim"
  wait "$launcher"; local status=$?
  if [[ $status -eq 143 && -n "$victim" && -e "$out.checkpoint" && ! -e "$out" && ! -e "$out.partial" ]] \
     && [[ $(grep -c "interrupted (signal 15)" "$out.log") -eq 1 ]]; then
    echo "ok: SIGTERM to rank $((k - 1)) alone stopped the $k ranks with one checkpoint and one message (exit 143)"
  else
    fail "SIGTERM to one rank: exit $status, victim '$victim', files: $(ls "$(dirname "$out")" | tr '\n' ' '), log: $(cat "$out.log")"
  fi
}

# no_gather FILE STEP OBSERVER [LEAST]: OBSERVER ran at least LEAST times
# (default 2) and STEP never gathered the system onto rank 0 (its profile
# row STEP.gather).
no_gather() {
  /usr/bin/python3 - "$@" <<'PY' || failures=$((failures + 1))
import h5py, sys
path, step, observer = sys.argv[1:4]
least = int(sys.argv[4]) if len(sys.argv) > 4 else 2
profile = h5py.File(path, 'r')['profile']
calls = {s.decode(): c for s, c in zip(profile['system'][()], profile['calls'][()])}
observed = calls.get(observer, 0)
if observed < least: sys.exit(f"FAIL: {path}: {observer} ran {observed} times")
gathers = calls.get(f'{step}.gather')
if gathers != 0: sys.exit(f"FAIL: {path}: the observers gathered the system {gathers} times")
print(f"ok: {path}: {observed} observations, no gather")
PY
}

# rank_peaks NP ARGS...: granflow ARGS on NP ranks; prints "rank kB exit-code"
# per rank, its peak resident memory (each rank writes its own line: no
# interleaving).
rank_peaks() {
  local np=$1
  shift
  rm -f "$work"/peak.*
  "$mpiexec" -np "$np" --oversubscribe --bind-to none /usr/bin/python3 -c "
import os, resource, subprocess, sys
code = subprocess.run(sys.argv[2:]).returncode
rank = os.environ['OMPI_COMM_WORLD_RANK']
with open(f'{sys.argv[1]}/peak.{rank}', 'w') as out:
    print(rank, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, code, file=out)
" "$work" "$granflow" "$@"
  cat "$work"/peak.*
}
