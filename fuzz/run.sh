#!/bin/bash
# Build every libFuzzer harness with clang into build/fuzz/ and run each for SECONDS seconds
# (default 60) on a writable corpus, build/fuzz-corpus/<name>, seeded from fuzz/corpus/<name>.
# Usage: bash fuzz/run.sh [SECONDS [NAME...]] where NAME is obj, ply, vtk or off (default all).
# Prints one line per harness with the number of inputs it executed and whether it found
# anything; findings (crash-*, leak-*, timeout-*, oom-*) land in build/fuzz/ as
# <name>-crash-..., and the exit status is non-zero when there is one. `make fuzz` runs this.
# Reproduce a finding with: build/fuzz/fuzz_<name> build/fuzz/<name>-crash-...
set -u
seconds=${1:-60}
shift || true
names=${*:-obj ply vtk off}
cd "$(dirname "$0")/.."
CC=${FUZZ_CC:-}
if [ -z "$CC" ]; then
    for c in clang-14 clang; do
        if command -v "$c" > /dev/null 2>&1; then CC=$c; break; fi
    done
fi
if [ -z "$CC" ]; then
    echo "FAIL fuzz: no clang found (set FUZZ_CC)"
    exit 1
fi
mkdir -p build/fuzz
status=0
for name in $names; do
    bin=build/fuzz/fuzz_$name
    log=build/fuzz/fuzz_$name.log
    if ! "$CC" -std=c99 -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
        -o "$bin" "fuzz/fuzz_$name.c" -lm > "$log" 2>&1; then
        echo "FAIL fuzz-$name (does not build; see $log)"
        status=1
        continue
    fi
    mkdir -p "build/fuzz-corpus/$name"
    "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
        -artifact_prefix="build/fuzz/$name-" "build/fuzz-corpus/$name" "fuzz/corpus/$name" >> "$log" 2>&1
    rc=$?
    runs=$(sed -n 's/^stat::number_of_executed_units: *\([0-9]*\)$/\1/p' "$log" | tail -n 1)
    if [ $rc -eq 0 ]; then
        echo "ok fuzz-$name (${runs:-?} inputs in ${seconds} s, nothing found)"
    else
        echo "FAIL fuzz-$name (exit $rc after ${runs:-?} inputs; see $log and build/fuzz/$name-*)"
        grep -m 3 -E "ERROR|SUMMARY|deadly signal" "$log" | sed 's/^/    /'
        status=1
    fi
done
exit $status
