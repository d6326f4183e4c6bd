#!/bin/bash
# Replay each fuzz harness's seed corpus (fuzz/corpus/<name>) under gcc with AddressSanitizer
# and UndefinedBehaviorSanitizer, without libFuzzer; `make test` runs this. Prints one line per
# harness, "ok replay-<name> (N inputs)" or "FAIL replay-<name> ...", and exits non-zero when
# any harness fails to build, finds a problem or has no inputs.
set -u
cd "$(dirname "$0")/.."
CC=${CC:-gcc}
mkdir -p build/fuzz
names="obj ply vtk off"
# build the harnesses side by side (a binary exists only if its build succeeded), then replay
for name in $names; do
    rm -f "build/fuzz/replay_$name"
    $CC -std=c99 -g -O0 -fsanitize=address,undefined -fno-sanitize-recover=all \
        -Wall -Wextra -Werror -o "build/fuzz/replay_$name" "fuzz/fuzz_$name.c" fuzz/replay.c -lm \
        > "build/fuzz/replay_$name.log" 2>&1 &
done
wait
status=0
for name in $names; do
    bin=build/fuzz/replay_$name
    log=build/fuzz/replay_$name.log
    if [ ! -x "$bin" ]; then
        echo "FAIL replay-$name (does not build; see $log)"
        status=1
        continue
    fi
    if "$bin" "fuzz/corpus/$name" >> "$log" 2>&1; then
        count=$(sed -n 's/^replayed \([0-9]*\) inputs$/\1/p' "$log")
        if [ "${count:-0}" -gt 0 ]; then
            echo "ok replay-$name ($count inputs)"
        else
            echo "FAIL replay-$name (no inputs in fuzz/corpus/$name)"
            status=1
        fi
    else
        echo "FAIL replay-$name (exit $?; see $log)"
        tail -n 15 "$log" | sed 's/^/    /'
        status=1
    fi
done
exit $status
