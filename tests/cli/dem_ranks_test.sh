#!/usr/bin/env bash
# One soft-sphere system over MPI ranks (`mpirun -np K granflow run`, a
# -DGRANFLOW_MPI=ON build; systems/dem/dem_domain_step.hpp): every sphere's
# force is summed as on one rank, so every result is one rank's bit for bit:
#  - the shaken bed (walls on every side, a divider, the compartment flux
#    counted every step) on 2 and 3 ranks, frictionless and with friction,
#    with the slabs balanced by sphere count (the default) and left equal
#    (the upper ranks then hold no sphere at all);
#  - the deep vibrated bed, periodic sideways, with friction (the springs'
#    history crosses the slab boundaries) and particle frames;
#  - every observer runs by rank (their sums in the one-rank grouping): no
#    round gathers the bed; a fresh bed is made by parts: no rank's memory
#    grows with the whole bed;
#  - a run stopped on 2 ranks and extended on 3, and one stopped on one
#    process and extended on 2, equal the uninterrupted one-rank run; a
#    checkpoint is written by rank, with nothing gathered, and is one
#    process's array for array;
#  - SIGINT to mpirun stops every rank at one step with one checkpoint and
#    no result file, and 3 ranks finish the run; a rank killed outright ends
#    the job, and its last periodic checkpoint resumes it; SIGTERM to one
#    rank alone stops all three alike and 2 ranks finish the run: all equal
#    the uninterrupted one-rank run;
#  - what the step does not offer, and more ranks than layers, are refused
#    once, on rank 0, with exit status 2.
set -u
source "$(dirname "$0")/ranks_common.sh"  # GRANFLOW MPIEXEC SCENARIOS

bed="$scenarios/shaken_bed.toml"
deep="$scenarios/vibrated_bed.toml"
alike() {  # alike NAME SCENARIO ARGS...: one process, then 2 and 3 ranks
  local name="$1" scenario="$2"; shift 2
  "$granflow" run "$scenario" "$@" -q -o "$work/${name}_1.h5" || fail "one rank ($name) exited with $?"
  for k in 2 3; do
    ranks "$k" run "$scenario" "$@" -q -o "$work/${name}_$k.h5" > "$work/${name}_$k.log" 2>&1 \
      || fail "$k ranks ($name) exited with $?: $(cat "$work/${name}_$k.log")"
    agree "$work/${name}_1.h5" "$work/${name}_$k.h5" 0
  done
}
shaken=(--set run.t_stop=6 --set output.average_after=3 --set output.positions=all)
alike shaken "$bed" "${shaken[@]}"
alike shaken_friction "$bed" "${shaken[@]}" --set contact.friction=0.5
alike shaken_equal_slabs "$bed" "${shaken[@]}" --set balance.every_steps=0
deep_args=(--set run.t_stop=0.6 --set output.interval=0.2 --set contact.friction=0.3 --set output.positions=all)
alike deep_friction "$deep" "${deep_args[@]}"
# Every observer runs on every rank over its own spheres, the compartment
# sampler every step: no round gathers the bed onto rank 0.
for run in shaken_2 shaken_friction_3 deep_friction_3; do
  no_gather "$work/$run.h5" dem_domain_step observe_dem_energy
done

# No rank holds the whole bed: a fresh bed is made by parts and observed by
# rank. The growth of each rank's peak memory from a bed of 10^3 spheres to
# one of 10^6 on 2 ranks, against one process's growth: measured 0.91 on
# rank 0 (which also gathers the particle constants to write them) and
# 0.75 on rank 1; 2.28 and 1.33 when every rank built the whole bed and
# rank 0 gathered it to observe. 1.1 leaves room for the allocator.
bed_peaks() {  # NP COUNT
  rank_peaks "$1" run "$deep" --set 'system.box=[72,72,800]' --set 'bed.fill=[0,71,0,71,0.6,200.5]' \
    --set system.count="$2" --set run.t_stop=0.01 -q --threads 1 -o "$work/memory.h5"
}
/usr/bin/python3 - "$(bed_peaks 1 1000)" "$(bed_peaks 1 1000000)" "$(bed_peaks 2 1000)" "$(bed_peaks 2 1000000)" \
  <<'PY' || failures=$((failures + 1))
import sys
def rows(text):
    out = {int(r): (int(kb), int(code)) for r, kb, code in (line.split() for line in text.splitlines())}
    if any(code != 0 for _, code in out.values()): sys.exit(f"FAIL: a memory run exited with {out}")
    return {r: kb for r, (kb, _) in out.items()}
small1, whole, small2, split = (rows(t) for t in sys.argv[1:5])
growth = whole[0] - small1[0]
for rank in (0, 1):
    share = (split[rank] - small2[rank]) / growth
    if share > 1.1:
        sys.exit(f"FAIL: rank {rank} grows by {share:.2f} of one process's growth: it holds the whole bed")
    print(f"ok: rank {rank} grows by {share:.2f} of one process's growth "
          f"({(split[rank] - small2[rank]) // 1024} of {growth // 1024} MB)")
PY

# The bed lies in the lowest layers: the slabs move to it at the start.
ranks 3 run "$bed" "${shaken[@]}" -o "$work/balanced.h5" > "$work/balanced.log" 2>&1 || fail "balanced run exited with $?"
if [[ $(grep -c "the slabs now start at layers" "$work/balanced.log") -ge 1 ]]; then
  echo "ok: the slabs moved to the bed: $(grep -m1 -o 'the slabs now start at layers.*' "$work/balanced.log")"
else
  fail "the slabs did not move to the bed: $(cat "$work/balanced.log")"
fi
/usr/bin/python3 - "$work/balanced.h5" <<'PY' || failures=$((failures + 1))
import sys, h5py
d = h5py.File(sys.argv[1], "r")["parameters/derived"].attrs
if d["ranks"] != 3 or d["slab_layers"] < 3:
    sys.exit(f"FAIL: derived ranks {d['ranks']}, slab_layers {d['slab_layers']}")
print(f"ok: {d['ranks']:.0f} ranks over {d['slab_layers']:.0f} layers recorded")
PY

# Stopped and extended on another number of ranks. The first part stops
# between two output times: what it wrote at its stop is not in the
# extension, which is the one run to the later stop.
whole=("${deep_args[@]}" --set output.final_checkpoint=true)
"$granflow" run "$deep" "${whole[@]}" -q -o "$work/deep_whole.h5" || fail "one-rank reference exited with $?"
ranks 2 run "$deep" "${whole[@]}" --set run.t_stop=0.5 -q -o "$work/deep_2to3.h5" || fail "2-rank first part exited with $?"
"$granflow" run "$deep" "${whole[@]}" --set run.t_stop=0.5 -q -o "$work/deep_1to2.h5" || fail "one-rank first part exited with $?"
# The checkpoint written by rank (each rank its spheres and their lists
# and springs, nothing gathered) is one process's, array for array.
/usr/bin/python3 - "$work/deep_1to2.h5.checkpoint" "$work/deep_2to3.h5.checkpoint" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
def arrays(path):
    f = h5py.File(path, "r")
    names = [n.decode() for n in f["checkpoint/names"][()]]
    return {n: f[f"checkpoint/values/{k}"][()] for k, n in enumerate(names)
            if not n.startswith("provenance") and n not in ("derived/ranks", "derived/slab_layers")}
one, by_rank = arrays(sys.argv[1]), arrays(sys.argv[2])
differ = sorted(n for n in one.keys() | by_rank.keys()
                if n not in one or n not in by_rank or not np.array_equal(one[n], by_rank[n]))
if differ or not any(n == "kept/neighbours/rows/shear" and one[n].size for n in one):
    sys.exit(f"FAIL: the 2-rank checkpoint differs from one process's in {differ}")
print(f"ok: the 2-rank checkpoint is one process's in all {len(one)} arrays")
PY
ranks 3 run "$deep" "${whole[@]}" -q -o "$work/deep_2to3.h5" --resume || fail "3-rank extension exited with $?"
agree "$work/deep_whole.h5" "$work/deep_2to3.h5" 0
no_gather "$work/deep_2to3.h5" dem_domain_step observe_dem_energy 1  # its final checkpoint included
ranks 2 run "$deep" "${whole[@]}" -q -o "$work/deep_1to2.h5" --resume || fail "2-rank extension exited with $?"
agree "$work/deep_whole.h5" "$work/deep_1to2.h5" 0

# The same where the first part's stop is no output time: its last step's
# energy terms, which the ranks add at the next gather, are in the
# checkpoint's ledger all the same.
short_bed=(-q --set output.final_checkpoint=true --set run.t_stop=0.02)
"$granflow" run "$deep" "${short_bed[@]}" -o "$work/short_whole.h5" || fail "one-rank reference exited with $?"
ranks 2 run "$deep" "${short_bed[@]}" --set run.t_stop=0.01 -o "$work/short_2to3.h5" || fail "2-rank first part exited with $?"
ranks 3 run "$deep" "${short_bed[@]}" -o "$work/short_2to3.h5" --resume || fail "3-rank extension exited with $?"
agree "$work/short_whole.h5" "$work/short_2to3.h5" 0

# Equal slabs leave the upper ranks with no sphere: resumed on 3 ranks, each
# reads its (empty) part, and all decide alike whether to lend it (they
# once did not, and the run hung).
equal=(-q --set output.final_checkpoint=true --set balance.every_steps=0 --set output.average_after=1)
"$granflow" run "$bed" "${equal[@]}" --set run.t_stop=3 -o "$work/equal_whole.h5" || fail "one-rank reference exited with $?"
ranks 3 run "$bed" "${equal[@]}" --set run.t_stop=2 -o "$work/equal_3.h5" || fail "3-rank first part exited with $?"
timeout 120 "$mpiexec" -np 3 --oversubscribe --bind-to none "$granflow" run "$bed" "${equal[@]}" --set run.t_stop=3 \
  -o "$work/equal_3.h5" --resume || fail "3-rank resume with empty ranks exited with $?"
agree "$work/equal_whole.h5" "$work/equal_3.h5" 0

# SIGINT on 2 ranks, finished on 3; a rank killed outright, resumed from
# the last periodic checkpoint; SIGTERM to the last of 3 ranks alone,
# finished on 2: all give the one-rank result bit for bit.
long_bed=(--set run.t_stop=12 --set output.average_after=6 -q)
"$granflow" run "$bed" "${long_bed[@]}" -o "$work/bed_whole.h5" || fail "one-rank reference exited with $?"
interrupted 2 "$work/bed_cut.h5" run "$bed" "${long_bed[@]}"
ranks 3 run "$bed" "${long_bed[@]}" -o "$work/bed_cut.h5" --resume || fail "3-rank resume of the interrupted run exited with $?"
agree "$work/bed_whole.h5" "$work/bed_cut.h5" 0
killed 2 "$work/bed_killed.h5" run "$bed" "${long_bed[@]}" --set output.checkpoint_interval=0.3
ranks 2 run "$bed" "${long_bed[@]}" --set output.checkpoint_interval=0.3 -o "$work/bed_killed.h5" --resume \
  || fail "--resume after the killed rank exited with $?"
agree "$work/bed_whole.h5" "$work/bed_killed.h5" 0 parameters/toml  # which names the checkpoint interval
terminated 3 "$work/bed_termed.h5" run "$bed" "${long_bed[@]}"
ranks 2 run "$bed" "${long_bed[@]}" -o "$work/bed_termed.h5" --resume || fail "--resume after SIGTERM to one rank exited with $?"
agree "$work/bed_whole.h5" "$work/bed_termed.h5" 0

# Refused, once.
refused 'run.integrator = "position_verlet" (velocity_verlet is) is not offered' 2 run "$bed" "${shaken[@]}" \
  --set run.integrator=position_verlet
refused "neighbour.reorder = false" 2 run "$bed" "${shaken[@]}" --set neighbour.reorder=false
refused "3 ranks cannot split 2 cells along z" 3 run "$bed" "${shaken[@]}" --set 'system.box=[20,4,3]' \
  --set system.count=40 --set divider.height=1 --set shaking.amplitude=0.2

exit $((failures > 0))
