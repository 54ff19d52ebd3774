#!/bin/sh
# disim shol's uncertainty bands end to end in calm air (--speed-max-kmh 0:
# no airwake field is needed): shol.csv carries the band's columns after
# the first ten, stdout keeps its three columns, report.md has the bands
# section; --band-grid-csv (an earlier run's shol.csv as the second grid,
# here one without the band's columns)
# reaches the band's grid column at the direction it differs, and the
# report names it; the second grid found in the database (--band-grid
# auto), built (--band-grid default) or left out (none); bad --band-grid
# values and a missing CSV are refused; the aircraft's [model_error]
# reaches the bands.
# Usage: shol_bands_cli.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_shol_bands_XXXXXX)
fail=0
scen=$src/scenarios/cg47_uh60a.ini
"$disim" shol "$scen" --coupling one-way --speed-max-kmh 0 -o "$tmp/out" --db "$tmp/db" \
    > "$tmp/run.csv" 2> "$tmp/run.log" || { echo "the calm-air run failed"; cat "$tmp/run.log"; fail=1; }
head -1 "$tmp/out/shol.csv" | grep -qx "wod_dir_deg,max_speed_kt,max_speed_kmh,limit,margin_roll_deg,margin_pitch_deg,margin_long_pct,margin_lat_pct,margin_coll_pct,margin_pedal_pct,band_lo_kmh,band_hi_kmh,band_grid_kmh,band_window_kmh,band_sens_kmh,band_open_above,low_confidence,band_model_kmh" \
    || { echo "bad shol.csv header"; head -1 "$tmp/out/shol.csv"; fail=1; }
[ "$(head -1 "$tmp/run.csv")" = "wod_dir_deg,max_speed_kt,limit" ] && [ "$(wc -l < "$tmp/run.csv")" -eq 8 ] \
    || { echo "stdout: expected its three columns and 7 rows"; cat "$tmp/run.csv"; fail=1; }
grep -q '^## Uncertainty bands' "$tmp/out/report.md" && grep -q 'No second grid level was available' "$tmp/out/report.md" \
    || { echo "report.md: no bands section, or it does not say there was no second grid"; fail=1; }
# every direction passes the hover and nothing failed: band 0-0, open above, no grid column, and no
# limiting quantity for the UH-60A's validated error to move (model: not defined)
[ "$(grep -c ',0.000000,0.000000,nan,nan,nan,1,0,nan$' "$tmp/out/shol.csv")" -eq 7 ] \
    || { echo "shol.csv: expected 7 open bands of width 0 without a grid"; cat "$tmp/out/shol.csv"; fail=1; }
grep -q '"band": {"lo_kmh": 0, "hi_kmh": 0, "grid_kmh": null' "$tmp/out/shol.json" \
    || { echo "shol.json: no band"; fail=1; }
grep -q '^| head | 0.0 | 0.0-0.0 (nothing failed: open above) | .*, model: not defined | - | ok |$' "$tmp/out/report.md" \
    || { echo "report.md: head's band does not say the model's source is not defined"; grep '^| head' "$tmp/out/report.md"; fail=1; }
# the UH-60A's validated error reaches the bands from its file's [model_error] (GenHel's 1 kt row)
grep -q '"model_reference": "GenHel at 1 kt"}' "$tmp/out/shol.json" && ! grep -q 'states no validated error' "$tmp/out/report.md" \
    || { echo "the UH-60A's [model_error] did not reach the bands"; grep band_rule "$tmp/out/shol.json"; fail=1; }
# a second grid from a CSV of the first ten columns (as runs before the
# bands wrote it): red 60 at 10 km/h there
awk -F, -v OFS=, '$1 + 0 == -60 && NR > 1 { $2 = sprintf("%.6f", 10 / 3.6 / 0.514444); $3 = 10 } { NF = 10; print }' \
    "$tmp/out/shol.csv" > "$tmp/other.csv"
"$disim" shol "$scen" --coupling one-way --speed-max-kmh 0 -o "$tmp/out2" --db "$tmp/db" \
    --band-grid-csv "$tmp/other.csv" > /dev/null 2> "$tmp/run2.log" \
    || { echo "the run with --band-grid-csv failed"; cat "$tmp/run2.log"; fail=1; }
grep -Eq '^-60.000000,.*,0.000000,0.000000,(9.99999[0-9]|10.00000[0-9]),nan,nan,1,0,nan$' "$tmp/out2/shol.csv" \
    || { echo "shol.csv: red 60's grid column is not +10 km/h"; cat "$tmp/out2/shol.csv"; fail=1; }
grep -q '^| red 60 | 0.0 | 0.0-0.0 (nothing failed: open above) | grid +10.0 (' "$tmp/out2/report.md" \
    || { echo "report.md: red 60 does not name the second grid's +10 km/h"; grep 'red 60' "$tmp/out2/report.md"; fail=1; }
grep -q 'band red 60: 0 km/h, 0.0-0.0 km/h open above (grid +10.0' "$tmp/run2.log" \
    || { echo "stderr: no band line for red 60"; cat "$tmp/run2.log"; fail=1; }
# the second grid from the database (the small SFS2 case of shol_e2e, 10
# CFD iterations a field: the path, not the physics): --band-grid default
# builds the default field beside the coarse one; then auto finds it and
# builds nothing, and none leaves the grid out
sfs=$src/tests/couple/sfs2_uh60a.ini
"$disim" shol "$sfs" --coupling one-way --cfd-max-iter 10 --band-grid default -o "$tmp/s1" --db "$tmp/sdb" \
    > /dev/null 2> "$tmp/s1.log" || { echo "--band-grid default failed"; cat "$tmp/s1.log"; fail=1; }
[ "$(ls "$tmp/sdb/fields/"*_coarse_*.h5 "$tmp/sdb/fields/"*_default_*.h5 2>/dev/null | wc -l)" -eq 2 ] \
    || { echo "expected a coarse and a default field"; ls "$tmp/sdb/fields"; fail=1; }
"$disim" shol "$sfs" --coupling one-way --cfd-max-iter 10 -o "$tmp/s2" --db "$tmp/sdb" > /dev/null 2> "$tmp/s2.log" \
    || { echo "--band-grid auto failed"; cat "$tmp/s2.log"; fail=1; }
grep -q 'band head: .*(grid [-+][0-9.]* (default grid, one-way)' "$tmp/s2.log" \
    || { echo "auto: no grid spread from the database's default field"; cat "$tmp/s2.log"; fail=1; }
[ "$(ls "$tmp/sdb/fields/"*.h5 | wc -l)" -eq 2 ] || { echo "auto built a field"; fail=1; }
cmp -s "$tmp/s1/shol.csv" "$tmp/s2/shol.csv" || { echo "auto and default gave different bands"; fail=1; }
"$disim" shol "$sfs" --coupling one-way --cfd-max-iter 10 --band-grid none -o "$tmp/s3" --db "$tmp/sdb" > /dev/null \
    2> "$tmp/s3.log" && grep -q 'band head: .*(grid: no second grid' "$tmp/s3.log" \
    || { echo "--band-grid none kept a grid"; cat "$tmp/s3.log"; fail=1; }
# refused
"$disim" shol "$scen" --band-grid medium > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "band-grid 'medium'" "$tmp/bad.log" || { echo "--band-grid medium not refused"; fail=1; }
"$disim" shol "$scen" --coupling one-way --speed-max-kmh 0 -o "$tmp/out3" --db "$tmp/db" \
    --band-grid-csv "$tmp/none.csv" > /dev/null 2> "$tmp/bad2.log" && { echo "a missing --band-grid-csv passed"; fail=1; }
grep -q "none.csv" "$tmp/bad2.log" || { echo "the error does not name the missing CSV"; cat "$tmp/bad2.log"; fail=1; }
[ -e "$tmp/out3/shol.csv" ] && { echo "outputs written after the error"; fail=1; }
[ $fail -eq 0 ] && rm -rf "$tmp" || echo "kept $tmp"
exit $fail
