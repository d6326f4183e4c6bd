#!/bin/bash
# `make test`: everything the tests need, then every stage; one line per check and, last,
# exactly "N passed, N failed" over all stages.
#   deps       what the tests need is installed (installs it when it can)
#   compile    cloth.h in every configuration (C99/C11, C++11/17, gcc/clang, float/double, ...)
#   unit       the unit tests of every module, under ASan and UBSan
#   slow       the tests too slow under the sanitizers, optimized (build/physics_slow)
#   readme     the README's usage example compiles and runs
#   replay     every fuzz corpus replayed through its harness under gcc with ASan and UBSan
#   examples   the teaching examples build warning-free (C99 and C++11) and each runs its short check
cd "$(dirname "$0")/.."
export CLOTH_ROOT=$PWD
passed=0; failed=0
count() { # reads check lines on stdin, echoes them, tallies ok/FAIL
    while IFS= read -r line; do
        echo "$line"
        case "$line" in
            "ok "*) passed=$((passed+1)) ;;
            "FAIL "*) failed=$((failed+1)) ;;
        esac
    done
}
stage() { echo "== $1"; }

stage deps
if bash tests/deps.sh; then echo "ok   deps"; passed=$((passed+1)); else echo "FAIL deps"; failed=$((failed+1)); fi

stage compile
count < <(bash tests/compile_checks.sh 2>&1)

# program NAME TARGET: builds TARGET with make, runs it, shows its failures and tallies its
# last line ("N passed, N failed"); build/NAME-build.log and build/NAME.log keep the output.
program() {
    mkdir -p build
    if make -s "$2" >"build/$1-build.log" 2>&1; then
        "./$2" >"build/$1.log" 2>&1
        grep -E "^(ok|FAIL|    FAILED)" "build/$1.log" | grep -v "^ok"
        last=$(tail -n 1 "build/$1.log")
        if [[ "$last" =~ ^([0-9]+)\ passed,\ ([0-9]+)\ failed$ ]]; then
            echo "$1: $last"
            passed=$((passed+BASH_REMATCH[1])); failed=$((failed+BASH_REMATCH[2]))
        else
            echo "FAIL $1 (the test program did not finish; see build/$1.log)"; tail -20 "build/$1.log"; failed=$((failed+1))
        fi
    else
        echo "FAIL $1-build"; head -40 "build/$1-build.log"; failed=$((failed+1))
    fi
}

stage unit
program unit build/tests

stage slow
program slow build/physics_slow

stage readme
mkdir -p build/readme
awk '/<!-- readme-example:begin -->/{f=1;next}/<!-- readme-example:end -->/{f=0}f' README.md | sed '/^```/d' > build/readme/example.c
if [ -s build/readme/example.c ] && gcc -std=c99 -Wall -Wextra -Wpedantic -Werror -I. -o build/readme/example build/readme/example.c -lm >build/readme/log 2>&1 \
   && (cd build/readme && ./example >>log 2>&1); then echo "ok   readme-example"; passed=$((passed+1))
else echo "FAIL readme-example (build/readme/log)"; head -20 build/readme/log; failed=$((failed+1)); fi

stage replay
if [ -f fuzz/replay.sh ]; then count < <(bash fuzz/replay.sh 2>&1); else echo "FAIL replay (fuzz/replay.sh missing)"; failed=$((failed+1)); fi

stage examples
count < <(bash tests/examples.sh 2>&1)

echo "$passed passed, $failed failed"
[ $failed -eq 0 ]
