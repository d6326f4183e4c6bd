#!/bin/bash
# Strain limiting (piece def strain_limit, strain_limit_stiffening) on the hang scene: cost and
# strain against the stiffening, with bench/dynamics.c (multigrid PCG at 1e-3, dihedral
# bending, as bench/results/dynamics.md's tables). Writes bench/results/dynamics_strain_limit.csv
# (bench/dynamics.c's columns after machine, cpu and loadavg; the material column names the
# limit, e.g. cotton+limit0.04x100). About 1.5 minutes on a 2-core VM.
#
#   bash bench/strain_limit.sh
#
# Environment: CC (gcc), RUNS (3, the median's runs), LIMIT (0.04).
set -euo pipefail
cd "$(dirname "$0")/.."
CC=${CC:-gcc}
RUNS=${RUNS:-3}
LIMIT=${LIMIT:-0.04}
BIN=build/bench/dynamics_strain_limit
OUT=bench/results/dynamics_strain_limit.csv
mkdir -p build/bench bench/results
"$CC" -std=c99 -O2 -ffp-contract=off -DDYNAMICS_HAVE_MULTIGRID -o "$BIN" bench/dynamics.c -lm
MACHINE=$(uname -n)
CPU=$(grep -m1 '^model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//' || uname -m)
"$BIN" scene -n 2 -S header | head -n 1 | sed 's/^/machine,cpu,loadavg,/' > "$OUT"
row() { # integrator n runs [dynamics options...]
    local integrator=$1 n=$2 runs=$3
    shift 3
    local load
    load=$(cut -d' ' -f1 /proc/loadavg)
    echo "bench strain_limit: $integrator n=$n $*" >&2
    "$BIN" scene -H -n "$n" -i "$integrator" -t 1e-3 -p multigrid -K d -r "$runs" "$@" 2> /dev/null |
        sed "s/^/$MACHINE,\"$CPU\",$load,/" >> "$OUT"
}
for n in 32 64; do
    row lbe $n "$RUNS"
    for s in 3 10 30 100; do row lbe $n "$RUNS" -l "$LIMIT" -s $s; done
done
# Newton's backward Euler converges through the limiters (one run: about 15 s per run at 32)
row be 32 1
row be 32 1 -l "$LIMIT" -s 100
tail -n +2 "$OUT" | cut -d, -f5,7,8,20,29,31,40,41 | column -t -s,
