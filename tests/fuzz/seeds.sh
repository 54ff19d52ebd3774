#!/bin/sh
# seeds.sh BUILD_DIR OUT_DIR -- the seed corpora of every harness, from the
# repository's own files, into OUT_DIR/<harness>/ (run from anywhere):
#   ini             every .ini in the repository
#   scenario, aircraft, ship, task
#                   the .ini files whose first section is [scenario],
#                   [aircraft], [ship], [task]
#   station_script  the station scripts of the tests and docs, and a ramp
#   lcm_msg, sim_control, lcm_log
#                   written by BUILD_DIR/tests/fuzz/fuzz_seeds with the
#                   project's encoders
#   field           a small airwake field written by cfd's own writer
#                   (fuzz_seeds), with its checksum
set -eu
[ $# -eq 2 ] || { echo "usage: seeds.sh BUILD_DIR OUT_DIR" >&2; exit 2; }
build=$(cd "$1" && pwd)
mkdir -p "$2"
out=$(cd "$2" && pwd)
cd "$(dirname "$0")/../.."
for h in ini scenario aircraft ship task station_script; do
    mkdir -p "$out/$h"
done
n=0
for f in $(git ls-files '*.ini' 2>/dev/null || find . -name '*.ini' -not -path './build*'); do
    n=$((n + 1))
    name="$n-$(basename "$f")"
    cp "$f" "$out/ini/$name"
    first=$(sed -n 's/^[[:space:]]*\[\([a-z_]*\).*/\1/p' "$f" | head -1)
    case "$first" in
    scenario | aircraft | ship | task) cp "$f" "$out/$first/$name" ;;
    esac
done
# station scripts: the format's example (sim/sim_station.h) and the edges
printf 'time_s,collective,long,lat,pedal\n0.0, 55, 50, 50, 50\n1.0, 60, 45, 50, 50 # a ramp\n1.0, 40, 45, 50, 50\n5, 40, 45, 55, 48\n' \
    > "$out/station_script/ramp.csv"
printf '# hold\n\n0,50,50,50,50\r\n' > "$out/station_script/hold.csv"
"$build/tests/fuzz/fuzz_seeds" "$out"
echo "seeds.sh: $(find "$out" -type f | wc -l) seeds in $out"
