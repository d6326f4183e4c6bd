#!/bin/bash
# The contact stress scenes (bench/stress.c, docs/scenes.md): builds with -O2, runs every scene at
# n = 16 and 32 (STRESS_NS to change, e.g. STRESS_NS="16 32 64"), each time-boxed: a scene
# stops after STRESS_BUDGET_S CPU seconds (default 300) and its row says status "timeout"
# with the frames it finished; a run the outer `timeout` (budget + 120 s wall) has to kill gets
# a row with status "killed in frame F" and the figures of the frames before it (or "killed"
# with none, when it did not finish its first frame). STRESS_SCENES picks scenes. Writes bench/results/stress.csv and
# bench/results/stress.png.
set -uo pipefail
cd "$(dirname "$0")/.."
CC=${CC:-gcc}
PYTHON=${PYTHON:-/usr/bin/python3}
NS=${STRESS_NS:-16 32}
export STRESS_BUDGET_S=${STRESS_BUDGET_S:-300}
SCENES=${STRESS_SCENES:-sphere funnel twist stack projectile capsule projectile_mesh}
OUT=bench/results/stress.csv
# the plot needs matplotlib: check now rather than after the runs
. bench/need_python.sh
bench_need_python stress matplotlib:python3-matplotlib
mkdir -p build/bench bench/results
# shellcheck disable=SC2086
"$CC" -std=c99 -O2 -ffp-contract=off ${BENCH_CFLAGS:-} -o build/bench/stress bench/stress.c -lm || exit 1
./build/bench/stress sphere 4 1 > build/bench/stress_header.csv || exit 1
# STRESS_APPEND=1 adds rows to an existing CSV instead of starting a new one
if [ "${STRESS_APPEND:-0}" != 1 ] || [ ! -s "$OUT" ]; then head -n 1 build/bench/stress_header.csv > "$OUT"; fi
columns=$(head -n 1 "$OUT" | tr ',' '\n' | wc -l)
for n in $NS; do
    for scene in $SCENES; do
        echo "bench stress: $scene n=$n (budget ${STRESS_BUDGET_S} s) ..." >&2
        progress=build/bench/stress_progress.csv
        rm -f "$progress"
        if ! row=$(STRESS_PROGRESS=$progress timeout $((${STRESS_BUDGET_S%.*} + 120)) ./build/bench/stress "$scene" "$n" 0 noheader); then
            row=""
        fi
        if [ -z "$row" ] && [ -s "$progress" ]; then # killed inside a frame: the figures of those before it
            done_frames=$(cut -d, -f6 "$progress")
            row="$(sed 's/,running$//' "$progress"),killed in frame $((done_frames + 1))"
        fi
        if [ -z "$row" ]; then # killed or failed before printing: a row with the status only
            load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo unknown)
            row="$(uname -n),unknown,$load,$scene,$n"
            for ((k = 6; k < columns; ++k)); do row="$row,"; done
            row="$row,killed"
        fi
        echo "$row" >> "$OUT"
        echo "$row" >&2
    done
done
"$PYTHON" bench/plot_stress.py "$OUT" bench/results/stress.png
