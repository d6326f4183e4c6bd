#!/bin/bash
# Makes sure what the tests need is installed: Debian's python3-meshio and python3-numpy for
# /usr/bin/python3 (the meshio interop tests), clang (compile checks). Installs with apt-get when
# missing and possible; otherwise says what to install and fails.
need=()
/usr/bin/python3 -c "import meshio, numpy" >/dev/null 2>&1 || need+=(python3-meshio python3-numpy)
command -v clang >/dev/null 2>&1 || need+=(clang)
command -v clang++ >/dev/null 2>&1 || need+=(clang)
[ ${#need[@]} -eq 0 ] && exit 0
echo "tests need: ${need[*]}; installing with apt-get"
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}") >/tmp/cloth-apt.log 2>&1
fi
if ! /usr/bin/python3 -c "import meshio, numpy" >/dev/null 2>&1; then
    echo "FAIL: /usr/bin/python3 cannot import meshio and numpy. Install them: apt-get install -y python3-meshio python3-numpy (log: /tmp/cloth-apt.log)"
    exit 1
fi
if ! command -v clang >/dev/null 2>&1; then
    echo "FAIL: clang is missing. Install it: apt-get install -y clang"
    exit 1
fi
exit 0
