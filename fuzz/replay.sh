#!/bin/bash
# Replay each fuzz harness's seed corpus (fuzz/corpus/<name>) under gcc with AddressSanitizer
# and UndefinedBehaviorSanitizer, without libFuzzer; `make test` runs this. Prints one line per
# harness, "ok replay-<name> (N inputs)" or "FAIL replay-<name> ...", and exits non-zero when
# any harness fails to build, finds a problem or has no inputs.
set -u
cd "$(dirname "$0")/.."
CC=${CC:-gcc}
mkdir -p build/fuzz
status=0
for name in obj ply vtk off; do
    bin=build/fuzz/replay_$name
    log=build/fuzz/replay_$name.log
    if ! $CC -std=c99 -g -O1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all \
        -Wall -Wextra -Werror -o "$bin" "fuzz/fuzz_$name.c" fuzz/replay.c -lm > "$log" 2>&1; then
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
