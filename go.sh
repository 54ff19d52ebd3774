#!/bin/sh
# disim set-up and entry point. On a fresh Debian 12 machine, as root:
#   ./go.sh quick  install what is missing, build, run the quick job: every
#                  scenario checked, the coarse one-way CG-47 + UH-60A
#                  envelope (8-12 minutes on 2 cores from an empty
#                  airwake database) into out/quick/cg47_uh60a
#   ./go.sh run    install what is missing, build, run the main job: every
#                  scenario checked; the builder in the background; a deck
#                  landing of each combination flown in real time in its
#                  airwake on LCM and logged, with a deck-camera video; the
#                  candidate SHOL of both, trim-based and flown by the
#                  replay pilot (coarse grid, one-way) into out/run
#   ./go.sh run-default  the default-grid two-way envelopes of both
#                  combinations (many hours on 2 cores) into out/<scenario>
#   ./go.sh test   install what is missing, build (sanitizers on), run all tests,
#                  then each libFuzzer harness for 5 s (about a minute; a
#                  crash, hang, leak or sanitizer report fails it)
# quick and run share the airwake database out/airwake-db: a field built by
# one is not built again by the other.
set -eu
cd "$(dirname "$0")"

PKGS="build-essential cmake pkg-config libinih-dev liblcm-dev liblcm-bin liblcm-java \
default-jdk-headless libglib2.0-dev libode-dev libosmesa6-dev libsundials-dev \
libhdf5-dev liblapacke-dev liblapack-dev libcairo2-dev ffmpeg iproute2 util-linux \
libsdl2-dev xvfb xauth imagemagick clang-14 libclang-rt-14-dev openfoam openmpi-bin"

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

# The fuzz harnesses' short run (tests/fuzz/README.md): clang 14 with
# libFuzzer, ASan and UBSan, only the harnesses and what they link built;
# each harness FUZZ_SECONDS (5) from the corpus kept in build-fuzz/corpus.
fuzz_short() {
    CC=clang-14 cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDISIM_FUZZ=ON -DDISIM_TESTS=OFF \
        -DDISIM_BENCH=OFF >/dev/null
    cmake --build build-fuzz -j "$(nproc)" --target fuzz fuzz_seeds
    sh tests/fuzz/run.sh build-fuzz "${FUZZ_SECONDS:-5}" build-fuzz/corpus
}

check_scenarios() {
    for s in scenarios/*.ini; do
        echo "== disim check $s"
        ./build/app/disim check "$s" >/dev/null
    done
}

# The main job: the builder in the background on the database;
# a port-side deck landing of each combination flown in real time by the
# automated pilot in the airwake as the builder finishes it (the best field
# there is: the CG-47's quick field from the landing's start, a finer one
# blended in as it comes), published on LCM and logged; the
# landing's deck-camera video; the candidate SHOL of CG-47 + UH-60A, then
# LPD-17 + SA365N, trim-based and flown by the replay pilot re-flying the
# logged landing at every WOD point; coarse grid, one-way. Progress on a
# terminal; everything under out/run/.
main_job() {
    disim=./build/app/disim db=out/airwake-db out=out/run
    t0=$(date +%s)
    stage() { printf '== [%s] stage %s\n' "$(elapsed)" "$*"; }
    elapsed() { e=$(($(date +%s) - t0)); printf '%d:%02d' $((e / 60)) $((e % 60)); }
    mkdir -p "$out" "$db"
    # Red and head winds are solved; green ones are their mirror images
    # (the ships are symmetric), made at once when the SHOL asks for them
    # and their red one is there (queued here, a green taken while its red
    # was still building would be solved). The builder builds a mirror
    # whose source is ready at once and what a running flight or SHOL
    # waits for before the rest (awdb/awdb.h, awdb_builder_run), so the
    # CG-47's envelope does not wait behind the LPD-17's solves.
    stage "1/7: the coarse ship-only fields queued, the builder started (its log: $db/builder.log)"
    # The CG-47 landing's quick field (twice the coarse spacing, under a
    # minute) first: the landing flies in it from its start, and in its
    # coarse field once that is built (blended in).
    $disim airwake scenarios/cg47_uh60a_flown.ini --wod-speed-kt 29.16 --wod-dir-deg 0 --rotor off --grid quick \
        --queue "$db" 2> /dev/null | sed 's/^/   /'
    for spec in "cg47_uh60a_flown 0" "cg47_uh60a_flown -30" "cg47_uh60a_flown -60" "cg47_uh60a_flown -90" \
        "lpd17_sa365n_flown -30" "lpd17_sa365n_flown 0" "lpd17_sa365n_flown -60" "lpd17_sa365n_flown -90"; do
        set -- $spec
        $disim airwake "scenarios/$1.ini" --wod-speed-kt 29.16 --wod-dir-deg "$2" --rotor off --grid coarse \
            --queue "$db" | sed 's/^/   /'
    done
    $disim airwaked "$db" --jobs 2 --no-lcm --exit-when-idle --max-iter 600 >> "$db/builder.log" 2>&1 &
    builder=$!
    trap 'kill $builder 2> /dev/null || true' EXIT INT TERM
    fly_landing() { # SCENARIO WOD_KT DIR_DEG NAME
        $disim fly "scenarios/$1.ini" --wod-speed-kt "$2" --wod-dir-deg "$3" --db "$db" --realtime \
            --pilot auto --task scenarios/tasks/land_port.ini --log "$out/$4.lcm" --csv "$out/$4.csv"
    }
    # wait for the quick field (at most 5 min; the landing flies the free
    # stream until a field is there if it is not)
    waited=0
    until $disim airwake scenarios/cg47_uh60a_flown.ini --wod-speed-kt 29.16 --wod-dir-deg 0 --rotor off \
        --grid quick --queue "$db" 2> /dev/null | grep -q ': ready$' || [ $waited -ge 300 ]; do
        sleep 2
        waited=$((waited + 2))
    done
    stage "2/7: CG-47 + UH-60A: the port-side landing in 25 kt ahead, sea state 4, flown in real time (about 1 min)"
    fly_landing cg47_uh60a_flown 25 0 landing_cg47_uh60a
    stage "3/7: its deck-camera video"
    $disim render "$out/landing_cg47_uh60a.lcm" -o "$out/landing_cg47_uh60a" --camera deck --size 1280x720 \
        --overlay hud --frames off
    stage "4/7: CG-47 + UH-60A: the candidate SHOL, trim-based and flown by the replay pilot"
    $disim shol scenarios/cg47_uh60a_flown.ini --db "$db" --cfd-max-iter 600 -o "$out/cg47_uh60a" \
        --method pilot --task "$out/landing_cg47_uh60a.lcm" > "$out/cg47_uh60a.csv"
    stage "5/7: LPD-17 + SA365N: the port-side landing in 20 kt from green 30, sea state 3, in real time"
    fly_landing lpd17_sa365n_flown 20 30 landing_lpd17_sa365n
    stage "6/7: LPD-17 + SA365N: the candidate SHOL, trim-based and flown by the replay pilot"
    $disim shol scenarios/lpd17_sa365n_flown.ini --db "$db" --cfd-max-iter 600 -o "$out/lpd17_sa365n" \
        --method pilot --task "$out/landing_lpd17_sa365n.lcm" > "$out/lpd17_sa365n.csv"
    stage "7/7: done in $(elapsed)"
    cat << EOF2
go.sh run: what went where (out/run/):
  landing_cg47_uh60a.lcm, landing_lpd17_sa365n.lcm  the landings' LCM logs (lcm-logplayer, disim render)
  landing_cg47_uh60a.csv, landing_*_task.json       their trajectories and task results
  landing_cg47_uh60a/deck.mp4                       the CG-47 landing seen from the deck
  cg47_uh60a/, lpd17_sa365n/                        report.md, shol_polar_flown.png (both envelopes),
                                                    shol.csv, shol.json, shol_flown.csv, shol_flown.json
  the airwake database: $db (builder.log)
EOF2
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
    install_deps
    build build -DCMAKE_BUILD_TYPE=Release
    check_scenarios
    main_job
    ;;
run-default)
    # The earlier main job: the default-grid two-way envelopes (many hours on 2 cores).
    install_deps
    build build -DCMAKE_BUILD_TYPE=Release
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
    # CI's set: everything but the label validation (the CFD cases on
    # reduced grids, the head-wind coupling cases on one database). The
    # validation set (ctest -L validation in a Release build, about half an
    # hour: the full-grid CFD cases at the documents' tolerances, shol_ige,
    # the head-wind coupling cases each on its own database) is run by
    # hand. A test that cannot run here skips (exit 77); under CI (CI set)
    # it fails instead: CI installs everything a test needs.
    ctest --output-on-failure -j "$(nproc)" -LE validation
    cd ..
    fuzz_short
    ;;
*)
    echo "usage: ./go.sh quick | ./go.sh run | ./go.sh run-default | ./go.sh test" >&2
    echo "  quick  build, check the scenarios, the coarse one-way CG-47 + UH-60A envelope (minutes)" >&2
    echo "  run    build, check the scenarios, the main job: flown landings, video, both SHOLs (coarse, one-way)" >&2
    echo "  run-default  build, check the scenarios, the default-grid two-way envelopes of both (hours)" >&2
    echo "  test   build with sanitizers, run every test, then each fuzz harness for 5 s" >&2
    exit 2
    ;;
esac
