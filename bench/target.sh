#!/bin/bash
# The two speed targets, measured in one run on one machine: the hang scene at n = 64 (the
# dynamics issue: at most a quarter of Bullet's ms per frame, worst edge strain under 5%) and
# the sphere scene at n = 64 with self-collision (the collisions issue: at most half of
# Bullet's ms per frame, zero intersecting pairs, zero penetration). cloth.h runs its fastest
# settings that keep those bounds, on 1 thread and on 2 (world def threads, built with
# -DCLOTH_THREADS -pthread; wall clock), against Bullet 3.24's btSoftBody (single thread,
# bench/bullet_scenes.cpp), all alternately, TARGET_ROUNDS times, so that every ratio compares
# figures taken minutes apart under the same load.
#
#   bash bench/target.sh
#
# Writes bench/results/target.csv (one row per scene, engine, settings and round) and
# bench/results/target.png (bench/plot_target.py). About 4 minutes per round on the 2-core VM.
#
# cloth.h settings (the README's "Where it stands" tables):
#   hang    bench/dynamics scene -n 64 -i lbe -p multigrid -t 1e-2 -l 0.04 -s 100 -K q -Z 1 -r 3
#           (CG 1e-2, 4% strain limiters, the quadratic bending energy lumped), 2 threads
#           with -j 2 -G 2 (the finest multigrid sweeps in two parts); and on 1 thread with
#           -t 3e-2, the loosest CG tolerance found to keep the worst strain under 5% (less
#           accurate: the README's "Speed of the dynamics" gives its deviation from the
#           converged solve); ms_per_frame is the median of 3 runs by the wall clock
#   sphere  bench/stress sphere 64 with STRESS_CG_TOLERANCE=1e-2 STRESS_OBSTACLE_ITERATIONS=2
#           STRESS_BENDING_LUMPED=1 STRESS_MG_LEVELS=2 STRESS_STRENGTH=0.2
#           STRESS_TRIAL_TOLERANCE=0.1 STRESS_TRIAL_UPDATE=0 STRESS_HOLD_TOUCHING=0
#           STRESS_SWEEP_PARTS=2 (CG 1e-2, 2 obstacle solves of which the first a trial at 0.1 on
#           the coarse multigrid levels of the last solve, every vertex held on its inertial
#           target: 0.75-0.87x the time of the default holding, which rests more smoothly;
#           lumped hinges, a two-level multigrid whose coarse level is smoothed, not factored,
#           whose aggregates follow the grid's rows and columns only (strength threshold 0.2:
#           its diagonal couplings are weak), its finest sweeps in two parts: side by side on 2
#           threads, a row of each in turn on 1), 2 threads with STRESS_THREADS=2;
#           ms_per_frame is the median frame (CPU on 1 thread, wall on 2), the exact
#           intersection check after every step untimed
#   Bullet  bullet_scenes hang|sphere 2 3 64 (bending links at distance 2, 3 runs, median by
#           the wall clock of each run's mean frame; its median frame by the CPU clock, the
#           statistic of cloth.h's sphere rows, in bullet_median_frame_ms)
#
# Columns: machine, cpu, loadavg, round, scene, engine, settings, threads, ms_per_frame,
# ratio (to Bullet's row of the same scene and round), target (the ratio to meet), strain_end,
# strain_worst, penetration_m (sphere), intersecting_pairs (cloth.h sphere: the most after any
# step), meets (1 when the ratio and the bounds hold: strain_worst < 5% for the hang; 0
# intersecting pairs and 0 penetration for the sphere), stream_2t_ratio (bench/cores.c's
# streaming loop, run just before the scene in that round: the time two copies take on two
# threads over one alone; near 1 the two threads ran on two cores, near 2 they shared one,
# which the 2-core VM was seen to do at some hours and not at others), bullet_median_frame_ms
# (every row: Bullet's median frame in that round and scene, CPU), median_frame_ratio (cloth.h's
# sphere rows: ms_per_frame, a median frame, over bullet_median_frame_ms; the like-for-like
# ratio beside `ratio`, which the target is judged on).
#
# Environment: CC (gcc), PYTHON (/usr/bin/python3), TARGET_ROUNDS (3).
set -euo pipefail
cd "$(dirname "$0")/.."
CC=${CC:-gcc}
PYTHON=${PYTHON:-/usr/bin/python3}
ROUNDS=${TARGET_ROUNDS:-3}
OUT=bench/results/target.csv
# the plot needs matplotlib: check now rather than after the runs
. bench/need_python.sh
bench_need_python target matplotlib:python3-matplotlib
mkdir -p build/bench bench/results
BULLET_BUILD_ONLY=1 bash bench/bullet.sh
"$CC" -std=c99 -O2 -ffp-contract=off -DDYNAMICS_HAVE_MULTIGRID -DCLOTH_THREADS -pthread \
    -o build/bench/dynamics_threads bench/dynamics.c -lm
"$CC" -std=c99 -O2 -ffp-contract=off -DCLOTH_THREADS -pthread -o build/bench/stress_threads bench/stress.c -lm

"$CC" -std=c99 -O2 -pthread -o build/bench/cores bench/cores.c

MACHINE=$(uname -n)
CPU=$(grep -m1 '^model name' /proc/cpuinfo 2> /dev/null | cut -d: -f2- | sed 's/^ *//; s/,/ /g' || true)
CPU=${CPU:-$(uname -m)}

# field HEADER ROW NAME: the value of column NAME of a CSV row, by its header line
field() {
    awk -v h="$1" -v r="$2" -v name="$3" 'BEGIN {
        n = split(h, hs, ","); split(r, rs, ",")
        for (i = 1; i <= n; ++i) if (hs[i] == name) { print rs[i]; exit }
        print "" }'
}

echo "machine,cpu,loadavg,round,scene,engine,settings,threads,ms_per_frame,ratio,target,strain_end,strain_worst,penetration_m,intersecting_pairs,meets,stream_2t_ratio,bullet_median_frame_ms,median_frame_ratio" > "$OUT"
HANG="scene -n 64 -i lbe -p multigrid -t 1e-2 -l 0.04 -s 100 -K q -Z 1 -r 3"
SPHERE_ENV="STRESS_CG_TOLERANCE=1e-2 STRESS_OBSTACLE_ITERATIONS=2 STRESS_BENDING_LUMPED=1 STRESS_MG_LEVELS=2 STRESS_STRENGTH=0.2 STRESS_TRIAL_TOLERANCE=0.1 STRESS_TRIAL_UPDATE=0 STRESS_HOLD_TOUCHING=0 STRESS_SWEEP_PARTS=2"
for round in $(seq "$ROUNDS"); do
    for scene in hang sphere; do
        out=$(./build/bench/cores)
        cores=$(field "$(echo "$out" | head -n 1)" "$(echo "$out" | tail -n 1)" stream_ratio)
        load=$(cut -d' ' -f1 /proc/loadavg)
        echo "bench target: round $round, $scene, Bullet (two-thread streaming ratio $cores) ..." >&2
        out=$(OMP_NUM_THREADS=1 ./build/bench/bullet_scenes "$scene" 2 3 64 2> /dev/null)
        h=$(echo "$out" | head -n 1)
        r=$(echo "$out" | tail -n 1)
        bullet_ms=$(field "$h" "$r" ms_per_frame_median)
        bullet_median=$(field "$h" "$r" cpu_ms_median_frame)
        target=0.25
        if [ "$scene" = sphere ]; then target=0.5; fi
        echo "$MACHINE,$CPU,$load,$round,$scene,bullet,bending links 2,1,$bullet_ms,1,$target,$(field "$h" "$r" max_strain_end),$(field "$h" "$r" max_strain_run),$(field "$h" "$r" penetration_max_m),,0,$cores,$bullet_median," >> "$OUT"
        # the hang also on 1 thread with the CG at 3e-2 ("loose": the speed-accuracy knob)
        runs="1 2"
        if [ "$scene" = hang ]; then runs="1 2 1loose"; fi
        for run in $runs; do
            threads=${run%loose}
            load=$(cut -d' ' -f1 /proc/loadavg)
            echo "bench target: round $round, $scene, cloth.h on $threads thread(s) ${run#$threads}..." >&2
            if [ "$scene" = hang ]; then
                extra=""
                tolerance=1e-2
                if [ "$threads" = 2 ]; then extra="-j 2 -G 2"; fi
                if [ "$run" = 1loose ]; then tolerance=3e-2; fi
                # shellcheck disable=SC2086
                out=$(./build/bench/dynamics_threads ${HANG/-t 1e-2/-t $tolerance} $extra 2> /dev/null)
                h=$(echo "$out" | head -n 1)
                r=$(echo "$out" | tail -n 1)
                ms=$(field "$h" "$r" ms_per_frame_wall)
                end=$(field "$h" "$r" strain_end)
                worst=$(field "$h" "$r" strain_worst)
                pen=""
                pairs=""
                settings="CG $tolerance + 4% limiters + quadratic lumped${extra:+ + sweep parts 2}"
                ok=$(awk -v w="$worst" 'BEGIN { print (w < 0.05) ? 1 : 0 }')
            else
                ./build/bench/stress_threads sphere 4 1 > build/bench/target_stress_header.csv
                h=$(head -n 1 build/bench/target_stress_header.csv)
                if [ "$threads" = 2 ]; then
                    r=$(env $SPHERE_ENV STRESS_THREADS=2 ./build/bench/stress_threads sphere 64 0 noheader)
                else
                    r=$(env $SPHERE_ENV ./build/bench/stress_threads sphere 64 0 noheader)
                fi
                ms=$(field "$h" "$r" ms_frame_median)
                end=$(field "$h" "$r" strain_end)
                worst=$(field "$h" "$r" strain_worst)
                pen=$(field "$h" "$r" penetration_m)
                pairs=$(field "$h" "$r" pairs_max)
                settings="CG 1e-2 + 2 obstacle solves (trial 0.1 on the last coarse levels) + inertial holds + lumped hinges + 2 levels + strength 0.2 + sweep parts 2"
                ok=$(awk -v p="$pen" -v q="$pairs" 'BEGIN { print (p <= 0 && q <= 0) ? 1 : 0 }')
            fi
            ratio=$(awk -v a="$ms" -v b="$bullet_ms" 'BEGIN { printf "%.3f", a / b }')
            median_ratio=""
            if [ "$scene" = sphere ]; then median_ratio=$(awk -v a="$ms" -v b="$bullet_median" 'BEGIN { printf "%.3f", a / b }'); fi
            meets=$(awk -v q="$ratio" -v t="$target" -v ok="$ok" 'BEGIN { print (q <= t && ok) ? 1 : 0 }')
            echo "$MACHINE,$CPU,$load,$round,$scene,cloth.h,$settings,$threads,$ms,$ratio,$target,$end,$worst,$pen,$pairs,$meets,$cores,$bullet_median,$median_ratio" >> "$OUT"
            tail -n 1 "$OUT" >&2
        done
    done
done
"$PYTHON" bench/plot_target.py "$OUT" bench/results/target.png
