#!/bin/bash
# Sourced by the bench scripts whose plots need Python modules, so that a missing module stops
# a run before its measurements, not after them:
#   . bench/need_python.sh; bench_need_python stress matplotlib:python3-matplotlib
# exits 1 with the Debian package to install when $PYTHON (default /usr/bin/python3) cannot
# import one of the named modules.
bench_need_python() {
    local who=$1 m python=${PYTHON:-/usr/bin/python3}
    shift
    for m in "$@"; do
        if ! "$python" -c "import ${m%%:*}" 2> /dev/null; then
            echo "bench $who: $python cannot import ${m%%:*}: install ${m#*:} (apt-get install -y ${m#*:})" >&2
            exit 1
        fi
    done
}
