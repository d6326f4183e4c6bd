#!/bin/bash
# Compiles cloth.h in every supported configuration and runs the result; one line per
# configuration: "ok compile-<name>" or "FAIL compile-<name>". Exit status: failures.
cd "$(dirname "$0")/.."
out=build/compile
mkdir -p $out
W="-Wall -Wextra -Wpedantic -Wshadow -Werror"
WC="$W -Wstrict-prototypes"
fails=0
check() { # name, command...
    local name=$1; shift
    if "$@" >$out/$name.log 2>&1 && ./$out/$name >>$out/$name.log 2>&1; then echo "ok   compile-$name"
    else echo "FAIL compile-$name (log: $out/$name.log)"; sed 's/^/    /' $out/$name.log | head -20; fails=$((fails+1)); fi
}
for cc in gcc clang; do
    for std in c99 c11; do
        for real in double float; do
            check $cc-$std-$real $cc -std=$std $WC -DCLOTH_REAL=$real -o $out/$cc-$std-$real tests/compile/impl.c tests/compile/user.c -lm
        done
    done
    check $cc-c99-static $cc -std=c99 $WC -DCLOTH_STATIC -o $out/$cc-c99-static tests/compile/user.c -lm
    check $cc-c99-nostdio $cc -std=c99 $WC -DCLOTH_NO_STDIO -o $out/$cc-c99-nostdio tests/compile/impl.c tests/compile/user.c -lm
    check $cc-custom-malloc $cc -std=c99 $WC -o $out/$cc-custom-malloc tests/compile/custom_malloc.c -lm
    # the thread pool compiled in (CLOTH_THREADS): a world on 2 threads matches 1 bit for bit
    check $cc-c99-threads $cc -std=c99 $WC -DCLOTH_THREADS -pthread -o $out/$cc-c99-threads tests/compile/threads.c -lm
    check $cc-c99-threads-float $cc -std=c99 $WC -DCLOTH_THREADS -DCLOTH_REAL=float -pthread -o $out/$cc-c99-threads-float tests/compile/threads.c -lm
done
for cxx in g++ clang++; do
    for std in c++11 c++17; do
        for real in double float; do
            check $cxx-$std-$real $cxx -std=$std $W -DCLOTH_REAL=$real -x c++ -o $out/$cxx-$std-$real tests/compile/impl.c tests/compile/user.c
        done
    done
    check $cxx-c++11-static $cxx -std=c++11 $W -DCLOTH_STATIC -x c++ -o $out/$cxx-c++11-static tests/compile/user.c
    check $cxx-c++11-threads $cxx -std=c++11 $W -DCLOTH_THREADS -pthread -x c++ -o $out/$cxx-c++11-threads tests/compile/threads.c
done
# A half-configured allocator must be refused at compile time.
if gcc -std=c99 -c -o $out/bad.o tests/compile/bad_malloc.c >$out/bad_malloc.log 2>&1; then
    echo "FAIL compile-refuses-half-allocator (compiled)"; fails=$((fails+1))
elif grep -q "define both CLOTH_MALLOC and CLOTH_FREE" $out/bad_malloc.log; then echo "ok   compile-refuses-half-allocator"
else echo "FAIL compile-refuses-half-allocator (wrong error)"; fails=$((fails+1)); fi
exit $fails
