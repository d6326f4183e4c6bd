#!/bin/bash
# The speed-accuracy knobs that have no table elsewhere, measured (bench/results/knobs.md):
#   1. the integrator, the time step (substeps) and the Newton iteration cap on the hang scene's
#      first 0.5 s (the fall and the catch; later the swinging cloth's paths part whatever the
#      step), against a reference that approximates the exact motion (bench/dynamics.c, mode
#      knobs: BDF2 on 32 substeps per frame, Newton converged, CG 1e-9)
#      -> bench/results/dynamics_knobs.csv
#   2. the collision thickness on the contact stress scenes (bench/stress.c with
#      STRESS_THICKNESS; every step checked by the exact triangle-triangle checker)
#      -> bench/results/thickness.csv
# and plots both into bench/results/knobs.png. The CG tolerance has its own mode
# (./build/bench/dynamics accuracy) and the resolution the speed table (bench/dynamics.sh).
# About 6 minutes on the 2-core VM.
#
#   bash bench/knobs.sh
#
# Environment: CC (gcc), RUNS (3, the median's runs), KNOBS_N (32, the hang's vertices per
# side), THICKNESSES ("0.00025 0.0005 0.001 0.002 0.004", m), THICKNESS_SCENES ("sphere:32
# funnel:32 stack:16", scene:n).
set -euo pipefail
cd "$(dirname "$0")/.."
CC=${CC:-gcc}
RUNS=${RUNS:-3}
KNOBS_N=${KNOBS_N:-32}
THICKNESSES=${THICKNESSES:-"0.00025 0.0005 0.001 0.002 0.004"}
THICKNESS_SCENES=${THICKNESS_SCENES:-"sphere:32 funnel:32 stack:16"}
mkdir -p build/bench bench/results
"$CC" -std=c99 -O2 -ffp-contract=off -DDYNAMICS_HAVE_MULTIGRID -o build/bench/dynamics_knobs bench/dynamics.c -lm
"$CC" -std=c99 -O2 -ffp-contract=off -o build/bench/stress bench/stress.c -lm
MACHINE=$(uname -n)
CPU=$(grep -m1 '^model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//' || uname -m)

# 1. integrator, substeps, Newton cap (multigrid PCG at 1e-3, dihedral bending: the speed table's set-up)
OUT=bench/results/dynamics_knobs.csv
echo "bench knobs: hang $KNOBS_N, integrator / substeps / Newton cap" >&2
LOAD=$(cut -d' ' -f1 /proc/loadavg)
./build/bench/dynamics_knobs knobs -n "$KNOBS_N" -t 1e-3 -p multigrid -K d -r "$RUNS" -f 30 |
    awk -v m="$MACHINE" -v c="\"$CPU\"" -v l="$LOAD" 'NR == 1 { print "machine,cpu,loadavg," $0; next } { print m "," c "," l "," $0 }' > "$OUT"

# 2. collision thickness
OUT2=bench/results/thickness.csv
first=1
for t in $THICKNESSES; do
    for sn in $THICKNESS_SCENES; do
        scene=${sn%%:*}
        n=${sn##*:}
        echo "bench knobs: $scene $n, thickness $t m" >&2
        if [ $first = 1 ]; then
            STRESS_THICKNESS=$t ./build/bench/stress "$scene" "$n" 0 | sed "1s/^/thickness_m,/; 2,\$s/^/$t,/" > "$OUT2"
            first=0
        else
            STRESS_THICKNESS=$t ./build/bench/stress "$scene" "$n" 0 noheader | sed "s/^/$t,/" >> "$OUT2"
        fi
    done
done

/usr/bin/python3 bench/plot_knobs.py bench/results/dynamics_knobs.csv bench/results/thickness.csv bench/results/knobs.png


