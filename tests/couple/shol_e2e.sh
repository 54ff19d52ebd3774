#!/bin/sh
# disim shol end to end on a small case: the command starts its own airwake
# builder, waits for the ship-only field (a few CFD iterations: this checks
# the path, not the physics), trims, and writes every output; a second run
# finds the field in the database and builds nothing; bad flags are refused.
# Usage: shol_e2e.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_shol_XXXXXX)
fail=0
"$disim" shol "$src/tests/couple/sfs2_uh60a.ini" --coupling one-way --cfd-max-iter 10 \
    -o "$tmp/out" --db "$tmp/db" > "$tmp/run1.csv" 2> "$tmp/run1.log" || { echo "first run failed"; cat "$tmp/run1.log"; fail=1; }
for f in shol.csv shol.json shol_polar.png shol_polar.svg report.md shol_trim_head.png; do
    [ -s "$tmp/out/$f" ] || { echo "missing output $f"; fail=1; }
done
head -1 "$tmp/out/shol.csv" | grep -q "^wod_dir_deg, *max_speed_kt, *max_speed_kmh, *limit" || { echo "bad csv header"; fail=1; }
# The report lists the field with its state: 10 iterations do not
# converge, so the field is the mean of its last 10 / 4 = 2 iterations.
grep -q "^## Airwake fields" "$tmp/out/report.md" && grep -q "^| SFS2_shiponly_.* | off | 10 | not converged, mean of last 2 |" "$tmp/out/report.md" \
    || { echo "report.md does not list the field and its state"; grep -A4 "Airwake fields" "$tmp/out/report.md"; fail=1; }
n1=$(ls "$tmp/db/fields/"*.h5 2>/dev/null | wc -l)
[ "$n1" -eq 1 ] || { echo "expected one field, found $n1"; fail=1; }
# disim trim --field: the one-way trim in that field at 5 km/h is the
# envelope's (the same pitch and pedal to the printed digits).
f1=$(ls "$tmp/db/fields/"*.h5 2>/dev/null | head -1)
"$disim" trim "$src/scenarios/aircraft/uh60a.ini" --hover-wod-kt 2.69978635 --field "$f1" --cg-S 0,0,-6 \
    > "$tmp/trim.csv" 2> "$tmp/trim.log" || { echo "disim trim --field failed"; cat "$tmp/trim.log"; fail=1; }
want=$(grep -o '"speed_kmh": 5, [^}]*' "$tmp/out/shol.json" | sed 's/"margins".*//; s/.*"pitch_deg": \([-0-9.]*\).*"pedal_pct": \([-0-9.]*\).*/\1 \2/')
got=$(tail -1 "$tmp/trim.csv" | awk -F, '{print $6, $5}')
echo "$want" | awk -v g="$got" '{split(g, a, " "); d1 = $1 - a[1]; d2 = $2 - a[2]; exit !(NF == 2 && d1 * d1 < 1e-6 && d2 * d2 < 1e-4)}' \
    || { echo "disim trim --field: pitch, pedal '$got' against the envelope's '$want'"; fail=1; }
"$disim" trim "$src/scenarios/aircraft/uh60a.ini" --hover-wod-kt 5 --field "$f1" --cg-S 0,0,-6 --wod-dir-deg 30 > /dev/null 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "wod-dir-deg 30.00: the field .* is from 0.00 deg" "$tmp/bad.log" || { echo "trim --field: direction mismatch accepted"; fail=1; }
"$disim" trim "$src/scenarios/aircraft/uh60a.ini" --hover-wod-kt 5 --field "$f1" --cg-S 0,0,-6000 --csv "$tmp/far.csv" > /dev/null 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "sampled outside the field" "$tmp/bad.log" && [ ! -e "$tmp/far.csv" ] || { echo "trim --field: CG outside the field accepted"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --rotor uniform --h-fine-m 2.0 --max-iter 2 \
    --threads 1 -o "$tmp/rotor.h5" 2> "$tmp/rotor.log" || { echo "rotor field not written"; cat "$tmp/rotor.log"; fail=1; }
"$disim" trim "$src/scenarios/aircraft/uh60a.ini" --hover-wod-kt 5 --field "$tmp/rotor.h5" --cg-S 0,0,-6 > /dev/null 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "rotor 'uniform': expected a ship-only field" "$tmp/bad.log" || { echo "trim --field: a rotor field accepted"; fail=1; }
"$disim" trim "$src/scenarios/aircraft/uh60a.ini" --hover-wod-kt 5 --field "$f1" > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "field needs --hover-wod-kt and --cg-S" "$tmp/bad.log" || { echo "trim --field without --cg-S accepted"; fail=1; }
# The rerun: the field is in the database; no builder is started.
"$disim" shol "$src/tests/couple/sfs2_uh60a.ini" --coupling one-way -o "$tmp/out2" --db "$tmp/db" > "$tmp/run2.csv" 2> "$tmp/run2.log" || { echo "rerun failed"; cat "$tmp/run2.log"; fail=1; }
grep -q "started an airwake builder" "$tmp/run2.log" && { echo "the rerun started a builder"; fail=1; }
cmp -s "$tmp/run1.csv" "$tmp/run2.csv" || { echo "the rerun gave another envelope"; fail=1; }
# Two runs at once on a fresh database share one builder: each field is
# built once (the builder log says "building NAME" once per key), whichever
# run started the builder.
"$disim" shol "$src/tests/couple/sfs2_uh60a.ini" --coupling one-way --cfd-max-iter 10 \
    -o "$tmp/outa" --db "$tmp/db2" > "$tmp/runa.csv" 2> "$tmp/runa.log" &
pa=$!
"$disim" shol "$src/tests/couple/sfs2_uh60a.ini" --coupling one-way --cfd-max-iter 10 \
    -o "$tmp/outb" --db "$tmp/db2" > "$tmp/runb.csv" 2> "$tmp/runb.log" &
pb=$!
wait $pa || { echo "concurrent run a failed"; cat "$tmp/runa.log"; fail=1; }
wait $pb || { echo "concurrent run b failed"; cat "$tmp/runb.log"; fail=1; }
nb=$(grep -c "building " "$tmp/db2/builder.log" 2>/dev/null)
nf=$(ls "$tmp/db2/fields/"*.h5 2>/dev/null | wc -l)
[ "$nb" = 1 ] && [ "$nf" -eq 1 ] || { echo "two runs: $nb builds and $nf fields (expected 1 and 1)"; cat "$tmp/db2/builder.log"; fail=1; }
cmp -s "$tmp/runa.csv" "$tmp/runb.csv" || { echo "the two concurrent runs gave different envelopes"; fail=1; }
# A sea state is the flight loop's: the trims are over a ship at rest.
"$disim" shol "$src/tests/sim/data/sea.ini" --db "$tmp/db" > /dev/null 2> "$tmp/sea.log"
[ $? -eq 1 ] && grep -q "sea.ini: \[sea\] state = 4: the candidate SHOL trims the aircraft over a ship at rest" "$tmp/sea.log" \
    || { echo "disim shol accepted a sea state"; cat "$tmp/sea.log"; fail=1; }
# Bad flags.
"$disim" shol "$src/tests/couple/sfs2_uh60a.ini" --grid medium > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "expected coarse, default or fine" "$tmp/bad.log" || { echo "bad --grid accepted"; fail=1; }
# --h-fine-m and --limiter (grid studies): the spacing reaches the grid;
# out of range, unknown and with --queue they are refused.
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --rotor off --h-fine-m 2.0 --max-iter 2 \
    --threads 1 -o "$tmp/h2.h5" 2> "$tmp/h2.log"
grep -q "= 71832 cells .* h_fine 2.00 m" "$tmp/h2.log" && [ -s "$tmp/h2.h5" ] || { echo "--h-fine-m 2.0 not applied"; cat "$tmp/h2.log"; fail=1; }
# The scenario's [cfd] max_iterations is the iteration limit of the fields
# it builds (--max-iter overrides it).
sed "s|^aircraft = .*|aircraft = $src/scenarios/aircraft/uh60a.ini|; s|^ship = .*|ship = $src/scenarios/ships/sfs2.ini|; s|^coupling = one-way|coupling = one-way\nmax_iterations = 3|" \
    "$src/tests/couple/sfs2_uh60a.ini" > "$tmp/it3.ini"
"$disim" airwake "$tmp/it3.ini" --wod-speed-kt 20 --rotor off --h-fine-m 2.0 --threads 1 -o "$tmp/it3.h5" 2> "$tmp/it3.log"
grep -q "wrote $tmp/it3.h5 (3 iterations" "$tmp/it3.log" || { echo "[cfd] max_iterations = 3 not applied"; cat "$tmp/it3.log"; fail=1; }
"$disim" airwake "$tmp/it3.ini" --wod-speed-kt 20 --rotor off --h-fine-m 2.0 --threads 1 --max-iter 4 -o "$tmp/it4.h5" 2> "$tmp/it4.log"
grep -q "wrote $tmp/it4.h5 (4 iterations" "$tmp/it4.log" || { echo "--max-iter did not override max_iterations"; cat "$tmp/it4.log"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --h-fine-m 0.01 -o "$tmp/h3.h5" 2> "$tmp/bad.log"
[ $? -ne 0 ] && grep -q "h-fine-m: expected a number in \[0.1, 5\], got '0.01'" "$tmp/bad.log" && [ ! -e "$tmp/h3.h5" ] || { echo "bad --h-fine-m accepted"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --h-fine-m 0.5 --queue "$tmp/q" 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "cannot be queued" "$tmp/bad.log" && [ ! -e "$tmp/q" ] || { echo "--h-fine-m with --queue accepted"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --limiter upwind -o "$tmp/h4.h5" 2> "$tmp/bad.log"
[ $? -ne 0 ] && grep -q "limiter: expected vanleer or minmod, got 'upwind'" "$tmp/bad.log" && [ ! -e "$tmp/h4.h5" ] || { echo "bad --limiter accepted"; fail=1; }
# --growth, --h-max-m and --focus-fwd-m (grid studies): the grading and
# the focus box's reach change the grid and are named in the field's grid
# attribute; out of range and with --queue they are refused.
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --rotor off --h-fine-m 2.0 --growth 1.3 \
    --h-max-m 10 --focus-fwd-m 30 --max-iter 2 --threads 1 -o "$tmp/g.h5" 2> "$tmp/g.log"
grep -q "= 47740 cells .* h_fine 2.00 m" "$tmp/g.log" && [ -s "$tmp/g.h5" ] && grep -aq "h2.000 m g1.30 hm10 ff30" "$tmp/g.h5" \
    || { echo "--growth/--h-max-m/--focus-fwd-m not applied"; cat "$tmp/g.log"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --growth 2 -o "$tmp/g2.h5" 2> "$tmp/bad.log"
[ $? -ne 0 ] && grep -q "growth: expected a number in \[1.01, 1.5\], got '2'" "$tmp/bad.log" && [ ! -e "$tmp/g2.h5" ] || { echo "bad --growth accepted"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --focus-fwd-m 30 --queue "$tmp/q" 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "cannot be queued" "$tmp/bad.log" && [ ! -e "$tmp/q" ] || { echo "--focus-fwd-m with --queue accepted"; fail=1; }
# --avg-window (studies of shedding fields): an unconverged field is the
# mean of that many iterations; with --queue it is refused.
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --rotor off --h-fine-m 2.0 --max-iter 12 \
    --avg-window 5 --threads 1 -o "$tmp/w.h5" 2> "$tmp/w.log"
grep -q "the field is the mean of the last 5 iterations" "$tmp/w.log" && [ -s "$tmp/w.h5" ] \
    || { echo "--avg-window not applied"; cat "$tmp/w.log"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --avg-window 50 --queue "$tmp/q" 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "avg-window.*cannot be queued" "$tmp/bad.log" && [ ! -e "$tmp/q" ] || { echo "--avg-window with --queue accepted"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --avg-window 1 -o "$tmp/w2.h5" 2> "$tmp/bad.log"
[ $? -ne 0 ] && grep -q "avg-window: expected a number in \[2, 1e+06\], got '1'" "$tmp/bad.log" && [ ! -e "$tmp/w2.h5" ] || { echo "bad --avg-window accepted"; fail=1; }
# --zone: a deck zone nested in a ship-only field of the same ship and
# direction; a rotor field, another direction or --queue are refused.
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 10 --rotor off --h-fine-m 2.0 --max-iter 2 \
    --threads 1 --zone "$tmp/h2.h5" -o "$tmp/z.h5" 2> "$tmp/z.log"
grep -q "deck zone .* cells" "$tmp/z.log" && [ -s "$tmp/z.h5" ] || { echo "--zone field not written"; cat "$tmp/z.log"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --rotor off --zone "$tmp/rotor.h5" -o "$tmp/z2.h5" 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "zone .*rotor.h5: expected a ship-only field" "$tmp/bad.log" && [ ! -e "$tmp/z2.h5" ] || { echo "--zone in a rotor field accepted"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --wod-dir-deg 30 --rotor off --zone "$tmp/h2.h5" -o "$tmp/z2.h5" 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "another WOD direction" "$tmp/bad.log" && [ ! -e "$tmp/z2.h5" ] || { echo "--zone in another direction's field accepted"; fail=1; }
"$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt 20 --zone "$tmp/h2.h5" --queue "$tmp/q" 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "cannot be queued" "$tmp/bad.log" && [ ! -e "$tmp/q" ] || { echo "--zone with --queue accepted"; fail=1; }
# disim probe: a profile that cannot be written (a full disk) is an error,
# not a short CSV with exit 0; disim validate refuses a bad --threads.
if [ -w /dev/full ]; then
    "$disim" probe "$tmp/h2.h5" --line 0,0,-5:0,0,-8:4 > /dev/full 2> "$tmp/bad.log"
    [ $? -eq 1 ] && grep -q "cannot write the profile" "$tmp/bad.log" || { echo "probe to a full disk: exit 0"; fail=1; }
fi
"$disim" validate cavity100 --threads x > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "threads: expected a number in \[0, 256\], got 'x'" "$tmp/bad.log" || { echo "validate --threads x accepted"; fail=1; }
cat "$tmp/run1.csv"
[ $fail -eq 0 ] && echo "shol_e2e: 1 passed, 0 failed" || echo "shol_e2e: 0 passed, 1 failed"
rm -rf "$tmp"
exit $fail
