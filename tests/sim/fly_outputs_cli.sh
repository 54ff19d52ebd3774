#!/bin/sh
# disim fly's outputs are checked before the flight: a target that exists
# and is not a regular file (a folder, a FIFO), one that is an input of the
# same run (the scenario, its aircraft or ship file), or a name given for
# two outputs is refused, exit 1, naming the flag, and nothing is flown or
# left behind; a regular file is replaced whole. disim shol checks its
# output folder before computing. A copy of scenarios/ is
# flown, so that a refusal that fails cannot damage the repository.
# Usage: fly_outputs_cli.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_flyout_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0 pass=0
cp -r "$src/scenarios" "$tmp/sc"
mkdir "$tmp/folder"
mkfifo "$tmp/fifo.csv"
cd "$tmp" || exit 1
args="sc/cg47_uh60a.ini --fast --duration 0.5 --wod-speed-kt 20 --wod-dir-deg 0 --db $tmp/db"
refused() { # EXPECTED-MESSAGE FLAGS...
    expect=$1
    shift
    out=$(timeout 60 "$disim" fly $args "$@" 2>&1)
    rc=$?
    if [ $rc -eq 1 ] && printf '%s' "$out" | grep -qF -- "$expect" && ! printf '%s' "$out" | grep -q " flown in "; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "FAIL fly $*: exit $rc, got: $out"
        echo "     expected exit 1 before flying and: $expect"
    fi
}
refused "--csv folder: a folder: expected a regular file or a new name" --csv folder
refused "--csv fifo.csv: a FIFO: expected a regular file or a new name" --csv fifo.csv
refused "--log fifo.csv: a FIFO: expected a regular file or a new name" --log fifo.csv
refused "--csv sc/cg47_uh60a.ini: an input of this run (sc/cg47_uh60a.ini)" --csv sc/cg47_uh60a.ini
refused "--csv ./sc/aircraft/uh60a.ini: an input of this run" --csv ./sc/aircraft/uh60a.ini
refused "--log sc/ships/cg47.ini: an input of this run" --log sc/ships/cg47.ini
refused "--log x.out: named as --csv too" --csv x.out --log x.out
refused "--log ./x.out: named as --csv too" --csv x.out --log ./x.out
cmp -s sc/cg47_uh60a.ini "$src/scenarios/cg47_uh60a.ini" && cmp -s sc/aircraft/uh60a.ini "$src/scenarios/aircraft/uh60a.ini" \
    && cmp -s sc/ships/cg47.ini "$src/scenarios/ships/cg47.ini" && pass=$((pass + 1)) \
    || { fail=$((fail + 1)); echo "FAIL an input was overwritten"; }
[ -p fifo.csv ] && [ -d folder ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL a refused target was replaced"; }
ls ./*.tmp* sc/*.tmp* folder/* > /dev/null 2>&1 && { fail=$((fail + 1)); echo "FAIL a file was left behind"; } || pass=$((pass + 1))
# a regular file is replaced whole
echo old > out.csv
"$disim" fly $args --csv out.csv 2> fly.log && head -n 1 out.csv | grep -q '^t_s,' && pass=$((pass + 1)) \
    || { fail=$((fail + 1)); echo "FAIL a regular --csv was not written"; cat fly.log; }
# disim shol -o: a file where the folder goes is refused before any work
# (no database opened, no envelope computed)
echo data > not_a_folder
out=$(timeout 120 "$disim" shol sc/cg47_uh60a.ini --cfd-max-iter 10 --speed-max-kmh 5 -o not_a_folder/sub \
    --db "$tmp/shol_db" 2>&1)
rc=$?
if [ $rc -eq 1 ] && printf '%s' "$out" | grep -qF "output folder: not_a_folder: not a folder (on the way to the folder not_a_folder/sub)" \
    && [ ! -e "$tmp/shol_db" ]; then pass=$((pass + 1)); else
    fail=$((fail + 1)); echo "FAIL shol -o FILE/sub: exit $rc, got: $out"; fi
# disim render: the still image's target and a log's frame folder the same
render_refused() { # EXPECTED-MESSAGE ARGS...
    expect=$1
    shift
    out=$(timeout 60 "$disim" render "$@" 2>&1)
    rc=$?
    if [ $rc -eq 1 ] && printf '%s' "$out" | grep -qF -- "$expect"; then pass=$((pass + 1)); else
        fail=$((fail + 1)); echo "FAIL render $*: exit $rc, got: $out"; echo "     expected exit 1 and: $expect"; fi
}
render_refused "-o sc/cg47_uh60a.ini: an input of this run" sc/cg47_uh60a.ini -o sc/cg47_uh60a.ini --size 64x48
render_refused "-o fifo.csv: a FIFO: expected a regular file" sc/cg47_uh60a.ini -o fifo.csv --size 64x48
render_refused "-o folder: a folder: expected a regular file" sc/cg47_uh60a.ini -o folder --size 64x48
render_refused "-o not_a_folder: not a folder" no_such.lcm -o not_a_folder/frames
cmp -s sc/cg47_uh60a.ini "$src/scenarios/cg47_uh60a.ini" && [ -p fifo.csv ] && pass=$((pass + 1)) \
    || { fail=$((fail + 1)); echo "FAIL render replaced its target"; }
echo "fly_outputs_cli: $pass passed, $fail failed"
[ $fail -eq 0 ]
