#!/bin/bash
# Build and run one module's tests alone (development only): wip/build_one.sh MODULE [FILTER] [extra cc flags]
# Compiles cloth.h with only core, math, mesh and MODULE's fragments, under ASan and UBSan.
set -e
m=$1; shift; f=${1:-}; shift || true
cd "$(dirname "$0")/.."
mkdir -p build
M=$(echo "$m" | tr a-z A-Z)
gcc -std=c99 -O1 -g -ffp-contract=off -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all \
  -Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes -Werror \
  -DCLOTH_WIP_ONLY -DCLOTH_WIP_$M -DTEST_ONLY_SUITE=$m "$@" \
  -o build/tests_$m tests/runner.c tests/impl.c tests/test_$m.c -lm
CLOTH_ROOT=$PWD ./build/tests_$m "$f"
