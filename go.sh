#!/bin/sh
# disim set-up and entry point. On a fresh Debian 12 machine, as root:
#   ./go.sh run    install what is missing, build, run the main job
#   ./go.sh test   install what is missing, build (sanitizers on), run all tests
set -eu
cd "$(dirname "$0")"

PKGS="build-essential cmake pkg-config libinih-dev liblcm-dev liblcm-bin liblcm-java \
default-jdk-headless libglib2.0-dev libode-dev libosmesa6-dev libsundials-dev \
libhdf5-dev liblapacke-dev liblapack-dev libcairo2-dev iproute2 util-linux"

install_deps() {
    missing=""
    for p in $PKGS; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing="$missing $p"
    done
    if [ -n "$missing" ]; then
        echo "go.sh: installing:$missing"
        if [ "$(id -u)" -ne 0 ]; then
            echo "go.sh: missing packages and not root: run as root or install:$missing" >&2
            exit 1
        fi
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq
        apt-get install -y -qq --no-install-recommends $missing
    fi
}

build() { # build DIR [cmake options]
    dir=$1
    shift
    cmake -S . -B "$dir" "$@" >/dev/null
    cmake --build "$dir" -j "$(nproc)"
}

case "${1:-}" in
run)
    install_deps
    build build -DCMAKE_BUILD_TYPE=Release
    # Main job: check every scenario, then the candidate SHOL envelopes of
    # both combinations (CG-47 + UH-60A first, then LPD-17 + SA365N) on the
    # default grid, sharing one airwake database (out/airwake-db).
    for s in scenarios/*.ini; do
        echo "== disim check $s"
        ./build/app/disim check "$s" >/dev/null
    done
    for s in scenarios/cg47_uh60a.ini scenarios/lpd17_sa365n.ini; do
        echo "== disim shol $s"
        ./build/app/disim shol "$s"
    done
    ;;
test)
    install_deps
    werror=OFF
    [ -n "${CI:-}" ] && werror=ON
    build build-test -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDISIM_SANITIZE=ON -DDISIM_WERROR=$werror
    cd build-test
    ctest --output-on-failure -j "$(nproc)"
    ;;
*)
    echo "usage: ./go.sh run | ./go.sh test" >&2
    exit 2
    ;;
esac
