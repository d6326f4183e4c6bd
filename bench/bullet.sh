#!/bin/bash
# Peer measurements: Bullet's btSoftBody (Debian's libbullet-dev, 3.24) on the standard "hang"
# and "sphere" scenes of docs/scenes.md, for comparison with cloth.h.
#
#   bash bench/bullet.sh            both scenes
#   bash bench/bullet.sh sphere     the named scenes only (hang, sphere)
#
# Installs libbullet-dev (and g++, pkg-config) with apt-get when missing, builds
# bench/bullet_scenes.cpp with g++ -O2 into build/bench/, runs it single-threaded and writes
# bench/results/bullet_<scene>.csv, one row per (bending, n), the machine and CPU in each row.
# See the top of bench/bullet_scenes.cpp for the settings and the columns' meaning.
#
# Environment:
#   BULLET_SIZES    vertices per side (default "16 32 64 128")
#   BULLET_RUNS     timed runs per size, median reported (default 3)
#   BULLET_RUNS_LARGE  timed runs for n >= 128 (default 1: with bending links, n = 128 costs
#                   about 20 s of setup (Bullet's generateBendingConstraints fills an
#                   n^2 x n^2 table) and 10-30 s of stepping per run; set 3 for the full set)
#   BULLET_BENDING  bending-link set-ups to run (default "2 0"): 2 = Bullet's usual cloth
#                   set-up, generateBendingConstraints(2) (the set-up docs/scenes.md
#                   describes); 0 = stretch links only
#   CXX             C++ compiler (default g++)
#   BULLET_BUILD_ONLY  1: install and build build/bench/bullet_scenes, run nothing (bench/target.sh)
set -euo pipefail
cd "$(dirname "$0")/.."

CXX=${CXX:-g++}
BULLET_SIZES=${BULLET_SIZES:-16 32 64 128}
BULLET_RUNS=${BULLET_RUNS:-3}
BULLET_RUNS_LARGE=${BULLET_RUNS_LARGE:-1}
BULLET_BENDING=${BULLET_BENDING:-2 0}
SCRATCH=build/bench
RESULTS=bench/results
SCENES=(hang sphere)
if [ $# -gt 0 ]; then SCENES=("$@"); fi
for scene in "${SCENES[@]}"; do
    case "$scene" in
    hang | sphere) ;;
    *) echo "bench bullet: no scene '$scene' (known: hang sphere)" >&2; exit 2 ;;
    esac
done

MACHINE=$(uname -n)
CPU=$(grep -m1 '^model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//' || true)
CPU=${CPU:-$(uname -m)}

# A CSV field, quoted when it needs to be.
csv_field() {
    case "$1" in
    *[,\"]*) printf '"%s"' "${1//\"/\"\"}" ;;
    *) printf '%s' "$1" ;;
    esac
}

# The compiler, pkg-config's entry for Bullet and the soft body headers are all there.
have_bullet() {
    command -v "$CXX" > /dev/null 2>&1 && command -v pkg-config > /dev/null 2>&1 &&
        pkg-config --exists bullet 2> /dev/null || return 1
    local flag
    for flag in $(pkg-config --cflags-only-I bullet); do
        [ -e "${flag#-I}/BulletSoftBody/btSoftBody.h" ] && return 0
    done
    return 1
}

if ! have_bullet; then
    packages="libbullet-dev pkg-config"
    if [ "$CXX" = g++ ]; then packages="$packages g++"; fi
    echo "bench bullet: Bullet's soft body library is missing: installing $packages ..."
    SUDO=
    if [ "$(id -u)" != 0 ] && command -v sudo > /dev/null 2>&1 && sudo -n true 2> /dev/null; then
        SUDO=sudo
    fi
    if command -v apt-get > /dev/null 2>&1 && { [ "$(id -u)" = 0 ] || [ -n "$SUDO" ]; }; then
        if $SUDO apt-get update -qq; then
            # shellcheck disable=SC2086
            $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $packages > /dev/null || true
        fi
    fi
    if ! have_bullet; then
        echo "bench bullet: cannot install it here; install Debian's packages $packages" >&2
        echo "bench bullet: (as root: apt-get update && apt-get install -y $packages) and rerun" >&2
        exit 1
    fi
fi

mkdir -p "$SCRATCH" "$RESULTS"
LIBS=$(pkg-config --libs bullet)
case " $LIBS " in
*" -lBulletSoftBody "*) ;;
*) LIBS="-lBulletSoftBody $LIBS" ;;
esac
echo "bench bullet: building bench/bullet_scenes.cpp (-O2) against Bullet $(pkg-config --modversion bullet) ..."
# shellcheck disable=SC2046,SC2086
"$CXX" -O2 $(pkg-config --cflags bullet) -o "$SCRATCH/bullet_scenes" bench/bullet_scenes.cpp $LIBS

if [ "${BULLET_BUILD_ONLY:-0}" = 1 ]; then exit 0; fi

m=$(csv_field "$MACHINE")
c=$(csv_field "$CPU")
for scene in "${SCENES[@]}"; do
    out="$SCRATCH/bullet_$scene.csv"
    : > "$out"
    for bending in $BULLET_BENDING; do
        for n in $BULLET_SIZES; do
            runs=$BULLET_RUNS
            if [ "$n" -ge 128 ]; then runs=$BULLET_RUNS_LARGE; fi
            echo "bench bullet: $scene, n = $n, bending links $bending, median of $runs ..."
            # One thread: Bullet's soft body solver runs on the calling thread; OpenMP (if
            # a build of Bullet used it) is held to one thread as well.
            OMP_NUM_THREADS=1 "./$SCRATCH/bullet_scenes" "$scene" "$bending" "$runs" "$n" \
                > "$SCRATCH/bullet_row.csv"
            if [ ! -s "$out" ]; then
                head -n 1 "$SCRATCH/bullet_row.csv" | sed 's/^/machine,cpu,/' > "$out"
            fi
            awk -v p="$m,$c," 'NR > 1 { print p $0 }' "$SCRATCH/bullet_row.csv" >> "$out"
        done
    done
    cp "$out" "$RESULTS/bullet_$scene.csv"
    cat "$RESULTS/bullet_$scene.csv"
done
