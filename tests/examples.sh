#!/bin/bash
# The teaching examples, as `make test` checks them: `make examples` builds every one warning-free
# (C99 at -O1, quicker to build than -O2, and a C++11 check), then each runs with --short and must exit 0 (each checks what it
# shows). One line per check: "ok   ..." or "FAIL ...". Logs in build/examples/.
cd "$(dirname "$0")/.."
mkdir -p build/examples
if make -s -j2 EXAMPLE_OPT=-O1 examples > build/examples/build.log 2>&1; then
    echo "ok   examples-build"
else
    echo "FAIL examples-build (build/examples/build.log)"; head -30 build/examples/build.log
fi
for src in examples/*.c; do
    name=$(basename "$src" .c)
    [ "$name" = demo ] && continue # `make demo`, a longer run
    if [ ! -x "build/examples/$name" ]; then
        echo "FAIL example-$name (not built: is it in the Makefile's EXAMPLES?)"
    elif timeout 120 "./build/examples/$name" --short > "build/examples/$name.log" 2>&1; then
        echo "ok   example-$name"
    else
        echo "FAIL example-$name (build/examples/$name.log)"; tail -5 "build/examples/$name.log"
    fi
done
