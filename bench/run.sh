#!/bin/bash
# cloth.h benchmarks: `make bench` (or `bash bench/run.sh`) runs every section below;
# `bash bench/run.sh io` runs the named sections only. Each section is a function
# bench_<name>, listed in SECTIONS, that writes its CSV (machine and CPU named) and PNG into
# bench/results/ and keeps its scratch files under build/bench/.
#
# Environment: CC (default gcc), BENCH_CFLAGS (extra flags for the C benchmarks), and
# PYTHON (default /usr/bin/python3, Debian's interpreter with python3-meshio, python3-numpy
# and python3-matplotlib).
set -euo pipefail
cd "$(dirname "$0")/.."

CC=${CC:-gcc}
BENCH_CFLAGS=${BENCH_CFLAGS:-}
PYTHON=${PYTHON:-/usr/bin/python3}
SCRATCH=build/bench
RESULTS=bench/results
SECTIONS=(io)
SECTIONS+=(ccd); bench_ccd() { mkdir -p build/bench && ${CC:-cc} -std=c99 -O2 -ffp-contract=off -o build/bench/ccd_sample bench/ccd_sample.c -lm && ./build/bench/ccd_sample tests/data/ccd-sample bench/results/ccd_sample.csv; }  # the CCD sample of Wang et al. 2021 (tests/data/ccd-sample): bench/results/ccd_sample.csv
SECTIONS+=(bvh); bench_bvh() { mkdir -p build/bench && ${CC:-cc} -std=c99 -O2 -ffp-contract=off -o build/bench/bvh bench/bvh.c -lm && ./build/bench/bvh; }  # bench/results/bvh.csv
SECTIONS+=(linsolve); bench_linsolve() { mkdir -p build/bench && ${CC:-cc} -std=c99 -O2 -ffp-contract=off -o build/bench/linsolve bench/linsolve.c -lm && ./build/bench/linsolve bench/results/linsolve.csv; }  # the PCG and its preconditioners on the hang scene's systems, n = 16..128: bench/results/linsolve{,_sequence}.csv (minutes)
SECTIONS+=(dynamics); bench_dynamics() { bash bench/dynamics.sh; }  # hang scene, every integrator, n = 16..128, against Bullet: bench/results/dynamics*.{csv,png}
SECTIONS+=(sphere); bench_sphere() { mkdir -p build/bench && ${CC:-cc} -std=c99 -O2 -ffp-contract=off -o build/bench/sphere bench/sphere.c -lm && { ./build/bench/sphere 16 180 0; for a in "16 180 1" "32 180 0" "32 180 1" "32 180 1 - 2" "32 180 1 - 4 0" "64 180 1 - 2" "64 180 1"; do ./build/bench/sphere $a | tail -n 1; done; } > bench/results/sphere.csv; }  # docs/scenes.md sphere through the world: obstacles after / in the solve, obstacle_iterations 2 / 4, contact springs off (the "4 0" row), n = 16, 32, 64 (about 70 s)
SECTIONS+=(stress); bench_stress() { bash bench/stress.sh; }  # docs/scenes.md contact stress scenes with the exact intersection checker: bench/results/stress.{csv,png}
SECTIONS+=(pictures); bench_pictures() { mkdir -p build/bench && ${CC:-cc} -std=c99 -O2 -ffp-contract=off -o build/bench/stress_pictures bench/stress_pictures.c -lm && ./build/bench/stress_pictures 16; }  # one picture per stress scene: bench/results/stress_scenes.png
SECTIONS+=(knobs); bench_knobs() { bash bench/knobs.sh; }  # integrator, substeps, Newton cap (hang 32) and collision thickness (stress scenes) against speed: bench/results/{dynamics_knobs,thickness}.csv, knobs.png
SECTIONS+=(lumped); bench_lumped() { mkdir -p build/bench && ${CC:-cc} -std=c99 -O2 -ffp-contract=off -o build/bench/lumped bench/lumped.c -lm && { for a in "32 60" "64 60" "128 60" "32 60 q" "64 60 q"; do ./build/bench/lumped path $a; done | awk 'NR == 1 || !/^bending,n,/'; for n in 32 64 128; do ./build/bench/lumped spin $n; done | awk 'NR == 1 || !/^n,/'; ./build/bench/lumped cantilever; } > bench/results/lumped.csv; }  # lumped bending's accuracy: hang paths against exact bending and against halving the step (dihedral 32-128, quadratic 32-64), a turning cloth's energy, the cantilever where it fails (about 6 min)
SECTIONS+=(drape); bench_drape() { mkdir -p build/bench && ${CC:-cc} -std=c99 -O2 -ffp-contract=off -o build/bench/drape bench/drape.c -lm && { ./build/bench/drape 32 24; DRAPE_TRIAL_TOLERANCE=1e-3 ./build/bench/drape 32 24 | tail -n +2; DRAPE_CG_TOLERANCE=1e-2 DRAPE_OBSTACLE_ITERATIONS=2 ./build/bench/drape 32 96 | tail -n +2; DRAPE_CG_TOLERANCE=1e-2 DRAPE_OBSTACLE_ITERATIONS=2 DRAPE_TRIAL_TOLERANCE=0.1 ./build/bench/drape 32 96 | tail -n +2; } > bench/results/drape.csv; }  # how the 32 x 32 sphere drape comes to rest over many paths: the defaults (24 paths) and CG 1e-2 with 2 obstacle solves (96 paths), each without and with a trial solve (about 8 min)
SECTIONS+=(bullet); bench_bullet() { bash bench/bullet.sh; }  # Bullet 3.24 btSoftBody peer figures: bench/results/bullet_{hang,sphere}.csv
SECTIONS+=(target); bench_target() { bash bench/target.sh; }  # the two speed targets (hang 64, sphere 64) against Bullet in one alternating run, 1 and 2 threads: bench/results/target.{csv,png} (about 12 min)

MACHINE=$(uname -n)
CPU=$(grep -m1 '^model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//' || true)
CPU=${CPU:-$(uname -m)}

# A CSV field, quoted when it needs to be.
csv_field() {
    case "$1" in
    *[,\"]*) printf '"%s"' "${1//\"/\"\"}" ;;
    *) printf '%s' "$1" ;;
    esac
}

. bench/need_python.sh

# ---- io: loading a 1,001,112-triangle mesh, cloth.h against meshio ----------------------
# Columns: machine,cpu,format,triangles,reader,median_s,runs,ratio_to_cloth_h,median_cpu_s,
# cpu_ratio_to_cloth_h,loadavg. median_s is wall clock (file read included); ratio_to_cloth_h
# is the reader's median over cloth.h's median for the same file (1 for cloth.h itself; 12
# means cloth.h is 12 times faster); the cpu_ columns are the same for process CPU time, which
# other load on a shared machine disturbs less; loadavg is the 1-minute load average when the
# section started (compare it with the number of cores).
bench_io() {
    local load
    load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo unknown)
    bench_need_python io meshio:python3-meshio matplotlib:python3-matplotlib
    echo "bench io: building bench/io_load.c (-O2) ..."
    # shellcheck disable=SC2086
    "$CC" -std=c99 -O2 $BENCH_CFLAGS -o "$SCRATCH/io_load" bench/io_load.c -lm
    echo "bench io: cloth.h writes and reads the mesh (median of 5) ..."
    "./$SCRATCH/io_load" "$SCRATCH" 5 > "$SCRATCH/io_cloth.csv"
    echo "bench io: meshio reads the same files (median of 3) ..."
    "$PYTHON" bench/io_meshio.py "$SCRATCH" 3 > "$SCRATCH/io_meshio.csv"
    {
        echo "machine,cpu,format,triangles,reader,median_s,runs,ratio_to_cloth_h,median_cpu_s,cpu_ratio_to_cloth_h,loadavg"
        awk -F, -v m="$(csv_field "$MACHINE")" -v c="$(csv_field "$CPU")" -v l="$load" '
            FNR == NR { base[$1] = $4; cbase[$1] = $6 }
            { n++; for (k = 1; k <= 6; ++k) f[n, k] = $k }
            END {
                for (i = 1; i <= n; ++i) {
                    x = f[i, 1]
                    if (!(x in base) || base[x] <= 0 || cbase[x] <= 0) { print "bench io: no cloth.h time for " x > "/dev/stderr"; exit 1 }
                    printf "%s,%s,%s,%s,%s,%s,%s,%.3f,%s,%.3f,%s\n", m, c, x, f[i, 2], f[i, 3], f[i, 4], f[i, 5],
                           f[i, 4] / base[x], f[i, 6], f[i, 6] / cbase[x], l
                }
            }' "$SCRATCH/io_cloth.csv" "$SCRATCH/io_meshio.csv"
    } > "$RESULTS/io_load.csv"
    "$PYTHON" bench/plot_io.py "$RESULTS/io_load.csv" "$RESULTS/io_load.png"
    cat "$RESULTS/io_load.csv"
}

mkdir -p "$SCRATCH" "$RESULTS"
if [ $# -gt 0 ]; then SECTIONS=("$@"); fi
for section in "${SECTIONS[@]}"; do
    if ! declare -F "bench_$section" > /dev/null; then
        echo "bench: no section '$section' (known: $(declare -F | sed -n 's/^declare -f bench_//p' | tr '\n' ' '))" >&2
        exit 2
    fi
    "bench_$section"
done
