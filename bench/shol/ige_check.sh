#!/bin/sh
# ige_check.sh -- the ground-effect check of the two-way coupling (ctest
# shol_ige; about 3 minutes on 2 cores in the sanitizer build). A UH-60A
# hovers with its CG 6 m above a flat deck (bench/shol/ige/), hub about
# 0.95 R above it, in calm air (--speed-max-kmh 0: no ship-only field is
# needed), two-way coupling with the interaction velocity on the coarse
# grid, at most two coupled iterations (the calm point converges in one:
# change 2.0-2.5 %). In ground effect the coupled trim must need less
# collective than the free-air trim (Cheeseman and Bennett: about 7 % more
# thrust at the same power at z/R = 0.95, 3 % for the isolated rotor 1.44 R
# over the sea). Prints both and exits 1 if the sign is wrong.
# Usage: bench/shol/ige_check.sh DISIM [DIR]
set -eu
disim=$1
if [ -n "${2:-}" ]; then
    dir=$2
else
    dir=$(mktemp -d /tmp/disim_ige_XXXXXX)
    trap 'rm -rf "$dir"' EXIT
fi
here=$(dirname "$0")
"$disim" shol "$here/ige/flat_ige.ini" --db "$dir/db" -o "$dir/out" --speed-max-kmh 0 \
    --max-coupling-iter 2 --cfd-max-iter 300 > "$dir/run.csv" 2> "$dir/run.log"
# calm air only: no ship-only field was built (couple_trim, cmd_shol)
if ls "$dir/db/fields/" | grep -q shiponly; then
    echo "calm air only built a ship-only field"; exit 1
fi
# the coupling history rows of the calm-air point: | head | 0.0 | iter | thrust | coll | ...
rows=$(grep '^| head | 0.0 |' "$dir/out/report.md")
echo "$rows"
free=$(echo "$rows" | awk -F'|' '$4+0 == 0 {print $6+0}')
last=$(echo "$rows" | tail -1 | awk -F'|' '{print $6+0}')
echo "calm air: collective free air $free %, two-way $last %"
awk -v f="$free" -v c="$last" 'BEGIN { exit !(c < f) }' && { echo "ground effect: yes"; exit 0; }
echo "ground effect: NO (two-way collective not below free air)"; exit 1
