#!/bin/bash
# cloth.h dynamics benchmark: the standard "hang" scene (docs/scenes.md) for every
# integrator at n = 16, 32, 64, 128, against Bullet 3.24's btSoftBody figures.
#
#   bash bench/dynamics.sh
#
# Builds bench/dynamics.c (-O2 -ffp-contract=off) into build/bench/, runs the sets below and
# writes, every row naming the machine (uname -n) and the CPU model:
#   bench/results/dynamics.csv           one row per (set, integrator, n, ...) configuration
#   bench/results/dynamics_payuse.csv    cost of one step with bending / wind on and off
#   bench/results/dynamics_vs_bullet.csv linearized backward Euler against Bullet's hang
#   bench/results/dynamics_fit.csv       exponent of cost against vertex count
#   bench/results/dynamics.png           the plots (bench/plot_dynamics.py)
# and prints a summary. Cost: about 14 minutes of CPU time with the defaults, 3.3 of them the lumped set (one run on a
# 2-core Xeon VM took 19 minutes of wall time at a load average of 3 to 5.5 from other work). Bullet's figures come from bench/results/bullet_hang.csv; when it is
# missing or older than bench/bullet_scenes.cpp, `bash bench/bullet.sh hang` remakes it
# (minutes).
#
# Sets (column `set`):
#   main            every integrator, the library's defaults: cotton (cloth_default_material,
#                   areal density set to the scene's 0.1 kg/m^2), cloth_default_pcg_options()
#                   (tolerance 1e-6, at most 1000 iterations, block Jacobi)
#   tolerance       the CG tolerance as a speed-accuracy knob: 1e-3 and 1e-2 (linearized
#                   backward Euler at every n; Newton backward Euler and BDF2 at 1e-3)
#   stiff           cotton with its membrane 10 times stiffer ("cottonx10"), run because
#                   cotton's strain passes 5 % (linearized backward Euler, default CG)
#   preconditioner  every preconditioner this cloth.h has (linearized backward Euler, CG
#                   tolerance 1e-3, n = 32 and 64); block Jacobi's rows there are the
#                   tolerance set's. A multigrid preconditioner is found by compiling a probe
#                   for CLOTH_PRECONDITIONER_MULTIGRID.
#   lumped          lumped bending (piece def bending_lumped, bench/results/lumped.md): exact,
#                   lumped in the step and lumped in the preconditioner only, with the dihedral
#                   and the quadratic energy (linearized backward Euler, multigrid, CG 1e-3;
#                   the material column ends in +lumped or +lumped_preconditioner)
#
# Repetitions and skips: each configuration runs DYNAMICS_RUNS times (median reported) while
# the runs fit its CPU budget (a further run is started only if the runs so far plus one more
# stay within it); a configuration whose single run is projected past its limit is skipped,
# and its row says so: first by the previous size's time times the vertex ratio (cost cannot
# grow slower than the vertex count), then, for n >= 64, by a pilot of a few frames (whose
# figures the row then holds, marked as such; early frames are the cheapest of the scene for
# the implicit integrators, so a pilot under-estimates them).
#
# Environment:
#   CC, BENCH_CFLAGS, PYTHON    as bench/run.sh (gcc, none, /usr/bin/python3)
#   DYNAMICS_SIZES              vertices per side (default "16 32 64 128")
#   DYNAMICS_RUNS               timed runs per configuration (default 3)
#   DYNAMICS_FRAMES             frames per run (default 120 = the scene's 2 s)
#   DYNAMICS_LIMIT_S            main set: skip a configuration whose one run is projected to
#                               take more CPU seconds than this (default 120)
#   DYNAMICS_BUDGET_S           main set: CPU seconds of stepping per configuration within
#                               which further runs are made (default 45)
#   DYNAMICS_EXTRA_PRECONDITIONERS  NAME=VALUE pairs for preconditioner enum values the
#                               benchmark's table does not know yet (e.g. "multigrid=3")
#   DYNAMICS_SETS               the sets to run (default "main tolerance stiff preconditioner payuse")
#   DYNAMICS_PAYUSE_N           vertices per side of the pay-for-what-you-use scene (default 64)
set -euo pipefail
cd "$(dirname "$0")/.."

CC=${CC:-gcc}
BENCH_CFLAGS=${BENCH_CFLAGS:-}
PYTHON=${PYTHON:-/usr/bin/python3}
SIZES=${DYNAMICS_SIZES:-16 32 64 128}
RUNS=${DYNAMICS_RUNS:-3}
FRAMES=${DYNAMICS_FRAMES:-120}
LIMIT=${DYNAMICS_LIMIT_S:-120}
BUDGET=${DYNAMICS_BUDGET_S:-45}
EXTRA_PRECONDITIONERS=${DYNAMICS_EXTRA_PRECONDITIONERS:-}
SETS=${DYNAMICS_SETS:-main tolerance stiff preconditioner lumped payuse}
PAYUSE_N=${DYNAMICS_PAYUSE_N:-64}
SCRATCH=build/bench
RESULTS=bench/results
BIN=$SCRATCH/dynamics
OUT=$SCRATCH/dynamics_rows.csv
PAYUSE_OUT=$SCRATCH/dynamics_payuse_rows.csv

MACHINE=$(uname -n)
CPU=$(grep -m1 '^model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//' || true)
CPU=${CPU:-$(uname -m)}

csv_field() {
    case "$1" in
    *[,\"]*) printf '"%s"' "${1//\"/\"\"}" ;;
    *) printf '%s' "$1" ;;
    esac
}
PREFIX="$(csv_field "$MACHINE"),$(csv_field "$CPU")"
loadavg() { cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo unknown; }

mkdir -p "$SCRATCH" "$RESULTS"
start_time=$(date +%s)

# The plots need matplotlib and numpy: check now rather than after the runs.
. bench/need_python.sh
bench_need_python dynamics matplotlib:python3-matplotlib numpy:python3-numpy

# ---- build -------------------------------------------------------------------------------
FLAGS=""
probe=$SCRATCH/dynamics_probe.c
printf '#include "../../cloth.h"\nint dynamics_probe = (int)CLOTH_PRECONDITIONER_MULTIGRID;\n' > "$probe"
if "$CC" -std=c99 -fsyntax-only "$probe" 2> /dev/null; then FLAGS="-DDYNAMICS_HAVE_MULTIGRID"; fi
echo "bench dynamics: building bench/dynamics.c (-O2 -ffp-contract=off${FLAGS:+ $FLAGS}) ..."
# shellcheck disable=SC2086
"$CC" -std=c99 -O2 -ffp-contract=off $FLAGS $BENCH_CFLAGS -o "$BIN" bench/dynamics.c -lm
PRECONDITIONERS="$("$BIN" preconditioners | tr '\n' ' ') $EXTRA_PRECONDITIONERS"
echo "bench dynamics: machine $MACHINE, $CPU, $(nproc 2> /dev/null || echo '?') cores, load $(loadavg); preconditioners: $PRECONDITIONERS"

# ---- runs ----------------------------------------------------------------------------------
"$BIN" scene -n 2 -S header | head -n 1 | sed 's/^/machine,cpu,set,loadavg,/' > "$OUT"

last_cpu_s=0       # CPU seconds of one run of the last configuration that ran (0: none)
last_vertices=0
last_skipped=0

# run SET INTEGRATOR N LIMIT BUDGET [options for bench/dynamics.c ...]
run() {
    local set=$1 integ=$2 n=$3 limit=$4 budget=$5
    shift 5
    local load pilot=0 row status ms frames v=$((n * n))
    load=$(loadavg)
    if [ "$last_skipped" = 1 ]; then
        row=$("$BIN" scene -H -n "$n" -i "$integ" -f "$FRAMES" "$@" -S "the smaller size was already over the limit of $limit s")
    elif [ "$last_skipped" = 2 ]; then
        row=$("$BIN" scene -H -n "$n" -i "$integ" -f "$FRAMES" "$@" -S "the smaller size failed")
    elif [ "$last_cpu_s" != 0 ] && awk -v c="$last_cpu_s" -v a="$last_vertices" -v b="$v" -v l="$limit" 'BEGIN { exit !(c * b / a > l) }'; then
        row=$("$BIN" scene -H -n "$n" -i "$integ" -f "$FRAMES" "$@" \
            -S "projected at least $(awk -v c="$last_cpu_s" -v a="$last_vertices" -v b="$v" 'BEGIN { printf "%.0f", c * b / a }') s CPU per run (n = $(awk -v a="$last_vertices" 'BEGIN { printf "%d", sqrt(a) }') time x vertex ratio) > limit $limit s")
    else
        if [ "$n" -ge 128 ]; then pilot=3; elif [ "$n" -ge 64 ]; then pilot=6; fi
        if [ "$pilot" -ge "$FRAMES" ]; then pilot=0; fi
        echo "bench dynamics: $set, $integ, n = $n $* (load $load) ..." >&2
        row=$("$BIN" scene -H -n "$n" -i "$integ" -f "$FRAMES" -r "$RUNS" -B "$budget" -P "$pilot" -L "$limit" "$@")
    fi
    echo "$PREFIX,$set,$load,$row" >> "$OUT"
    echo "  $(echo "$row" | awk -F, '{ printf "%s n=%s %s: %s ms/frame CPU (%s wall), %s runs, cg/frame %s, newton/frame %s, strain %s (worst %s)", $4, $2, $10, $17, $20, $13, $26, $28, $37, $38 }') $(echo "$row" | cut -d, -f14)" >&2
    status=$(echo "$row" | cut -d, -f14)
    ms=$(echo "$row" | cut -d, -f17)
    frames=$(echo "$row" | cut -d, -f12)
    last_vertices=$v
    case "$status" in
    '"ok"')
        last_cpu_s=$(awk -v m="$ms" -v f="$frames" 'BEGIN { printf "%.3f", m * f / 1000 }')
        last_skipped=0 ;;
    '"failed'*) last_skipped=2 ;;
    *) last_skipped=1 ;;
    esac
}

# A series over the sizes: run SET INTEGRATOR LIMIT BUDGET OPTIONS... for each size.
series() {
    local set=$1 integ=$2 limit=$3 budget=$4 n
    shift 4
    last_cpu_s=0
    last_vertices=0
    last_skipped=0
    for n in $SIZES; do run "$set" "$integ" "$n" "$limit" "$budget" "$@"; done
}

for set in $SETS; do
    case "$set" in
    main)
        for integ in lbe se be bdf2; do series main "$integ" "$LIMIT" "$BUDGET"; done
        ;;
    tolerance)
        for tol in 1e-2 1e-3; do series tolerance lbe 60 30 -t "$tol"; done
        series tolerance be 60 20 -t 1e-3
        series tolerance bdf2 60 20 -t 1e-3
        ;;
    stiff)
        series stiff lbe 60 30 -M cottonx10
        ;;
    lumped)
        # lumped bending (piece def bending_lumped): in the step (-Z 1) and in the
        # preconditioner only (-Z 2), both energies, against exact dihedral bending at the same
        # tolerance (the main set's rows are the exact quadratic ones)
        series lumped lbe 60 30 -t 1e-3 -p multigrid -K d
        series lumped lbe 60 30 -t 1e-3 -p multigrid -K q
        for K in d q; do for Z in 1 2; do series lumped lbe 60 30 -t 1e-3 -p multigrid -K "$K" -Z "$Z"; done; done
        ;;
    preconditioner)
        for p in $PRECONDITIONERS; do
            [ "$p" = block_jacobi ] && continue
            last_cpu_s=0; last_vertices=0; last_skipped=0
            for n in 32 64; do run preconditioner lbe "$n" 40 20 -t 1e-3 -p "$p"; done
        done
        ;;
    payuse)
        echo "bench dynamics: pay for what you use, n = $PAYUSE_N, 15 steps from the same state per variant ..." >&2
        load=$(loadavg)
        "$BIN" payuse -n "$PAYUSE_N" -i lbe -r 15 | awk -v p="$PREFIX,$load," 'NR == 1 { print "machine,cpu,loadavg," $0; next } { print p $0 }' > "$PAYUSE_OUT"
        cp "$PAYUSE_OUT" "$RESULTS/dynamics_payuse.csv"
        ;;
    *)
        echo "bench dynamics: no set '$set' (known: main tolerance stiff preconditioner lumped payuse)" >&2
        exit 2
        ;;
    esac
done
# Rows of sets not run this time are kept from the last results (DYNAMICS_SETS=preconditioner
# refreshes those rows only).
"$PYTHON" - "$OUT" "$RESULTS/dynamics.csv" "$SETS" << 'EOF'
import csv, os, sys
new_path, old_path, sets = sys.argv[1], sys.argv[2], sys.argv[3].split()
with open(new_path, newline="") as f:
    new = list(csv.reader(f))
kept = []
if os.path.exists(old_path):
    with open(old_path, newline="") as f:
        old = list(csv.reader(f))
    if old and old[0] == new[0]:
        col = new[0].index("set")
        kept = [r for r in old[1:] if r[col] not in sets]
with open(old_path, "w", newline="") as f:
    csv.writer(f, lineterminator="\n").writerows([new[0]] + kept + new[1:])
EOF

# ---- Bullet ---------------------------------------------------------------------------------
if [ ! -s "$RESULTS/bullet_hang.csv" ] || [ bench/bullet_scenes.cpp -nt "$RESULTS/bullet_hang.csv" ]; then
    echo "bench dynamics: bench/results/bullet_hang.csv is missing or older than bench/bullet_scenes.cpp: running bash bench/bullet.sh hang ..."
    bash bench/bullet.sh hang
else
    echo "bench dynamics: Bullet's figures from bench/results/bullet_hang.csv (newer than bench/bullet_scenes.cpp)"
fi

# ---- comparison, fit, plots, summary ---------------------------------------------------------
"$PYTHON" bench/plot_dynamics.py "$RESULTS" "$(csv_field "$MACHINE")" "$(csv_field "$CPU")"
echo "bench dynamics: done in $(($(date +%s) - start_time)) s wall"
