#!/bin/sh
# disim set-up and entry point. On a fresh Debian 12 machine, as root:
#   ./go.sh quick  install what is missing, build, run the quick job: every
#                  scenario checked, the coarse one-way CG-47 + UH-60A
#                  envelope (8-12 minutes on 2 cores from an empty
#                  airwake database) into out/quick/cg47_uh60a
#   ./go.sh run    install what is missing, build, run the main job: every
#                  scenario checked, the default-grid two-way envelopes of
#                  both combinations (many hours on 2 cores) into
#                  out/<scenario>
#   ./go.sh test   install what is missing, build (sanitizers on), run all tests
# quick and run share the airwake database out/airwake-db: a field built by
# one is not built again by the other.
set -eu
cd "$(dirname "$0")"

PKGS="build-essential cmake pkg-config libinih-dev liblcm-dev liblcm-bin liblcm-java \
default-jdk-headless libglib2.0-dev libode-dev libosmesa6-dev libsundials-dev \
libhdf5-dev liblapacke-dev liblapack-dev libcairo2-dev ffmpeg iproute2 util-linux"

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

check_scenarios() {
    for s in scenarios/*.ini; do
        echo "== disim check $s"
        ./build/app/disim check "$s" >/dev/null
    done
}

case "${1:-}" in
quick)
    install_deps
    build build -DCMAKE_BUILD_TYPE=Release
    # Quick job: check every scenario, then the candidate SHOL envelope of
    # CG-47 + UH-60A on the coarse grid, one-way (ship-only airwake, one
    # field per direction): the whole pipeline in minutes. The coarse grid
    # is not grid-converged: this shows the pipeline working, not a result.
    check_scenarios
    # The CFD cap of the measured figures (docs/benchmarks.md): crosswind
    # fields that shed stop there as the mean of their last iterations.
    echo "== disim shol scenarios/cg47_uh60a.ini --grid coarse --coupling one-way --cfd-max-iter 600"
    ./build/app/disim shol scenarios/cg47_uh60a.ini --grid coarse --coupling one-way --cfd-max-iter 600 \
        -o out/quick/cg47_uh60a --db out/airwake-db
    ;;
run)
    echo "go.sh run: the main job, the default-grid two-way envelopes of CG-47 + UH-60A and" \
        "LPD-17 + SA365N, takes many hours on 2 cores; ./go.sh quick is the variant that" \
        "finishes in 8-12 minutes (coarse grid, one-way, CG-47 + UH-60A)."
    install_deps
    build build -DCMAKE_BUILD_TYPE=Release
    # Main job: check every scenario, then the candidate SHOL envelopes of
    # both combinations (CG-47 + UH-60A first, then LPD-17 + SA365N) on the
    # default grid, sharing one airwake database (out/airwake-db).
    check_scenarios
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
    # the full-tolerance validation set (ctest -L validation, about half an
    # hour) is run by hand: CI runs the reduced cases
    ctest --output-on-failure -j "$(nproc)" -LE validation
    ;;
*)
    echo "usage: ./go.sh quick | ./go.sh run | ./go.sh test" >&2
    echo "  quick  build, check the scenarios, the coarse one-way CG-47 + UH-60A envelope (minutes)" >&2
    echo "  run    build, check the scenarios, the default-grid two-way envelopes of both (hours)" >&2
    echo "  test   build with sanitizers, run every test" >&2
    exit 2
    ;;
esac
