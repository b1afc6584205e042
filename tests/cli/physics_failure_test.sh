#!/usr/bin/env bash
# The time-stepped methods (soft spheres, SRD) when their input or their
# physics goes wrong: bad values stop with exit 2 and a message naming the
# key, a blow-up stops with exit 3 and a diagnosis, and nothing hangs,
# crashes or grows without bound. One check per class of failure.
set -u
granflow="$1"
scenarios="$2"
source "$(dirname "$0")/common.sh"
bed="$scenarios/shaken_bed.toml"
deep="$scenarios/vibrated_bed.toml"
tiny=(--set system.count=50 --set run.t_stop=2 --set output.average_after=1 -q)

# expect_status STATUS "what the message must contain" args... (each run at most 60 s)
expect_status() {
  local want="$1" needle="$2"; shift 2
  local output status
  output=$(timeout 60 "$granflow" "$@" 2>&1); status=$?
  if [[ $status -ne $want ]]; then
    echo "FAIL: '$*' exited with $status, expected $want"; echo "$output" | tail -5; failures=$((failures + 1))
  elif [[ "$output" != *"$needle"* ]]; then
    echo "FAIL: '$*' did not say '$needle':"; echo "$output" | tail -5; failures=$((failures + 1))
  else
    echo "ok: exit $want: $needle"
  fi
}

# Peak resident memory (kB) of one run.
peak_rss() {
  /usr/bin/python3 -c 'import resource, subprocess, sys
subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)' "$@"
}

# Memory does not grow with the length of a run, on one thread as on two.
for threads in 1 2; do
  short=$(peak_rss "$granflow" run "$bed" --set run.t_stop=10 --set output.average_after=1 --threads $threads -q \
    -o "$work/short.h5md")
  long=$(peak_rss "$granflow" run "$bed" --set run.t_stop=40 --set output.average_after=1 --threads $threads -q \
    -o "$work/long.h5md")
  # Outputs and averages add a few kB per time unit; a leak per step adds MBs.
  if (( long > short + short / 5 + 4096 )); then
    echo "FAIL: shaken_bed on $threads thread(s): peak RSS $short kB to t = 10, $long kB to t = 40"
    failures=$((failures + 1))
  else
    echo "ok: shaken_bed on $threads thread(s): peak RSS $short kB to t = 10, $long kB to t = 40"
  fi
done

echo "$failures failure(s)"
[[ $failures -eq 0 ]]
