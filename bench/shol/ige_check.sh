#!/bin/sh
# ige_check.sh -- the ground-effect check of the two-way coupling (ctest
# shol_ige; 1-1.5 minutes on 2 cores in Release, on the development machine).
# A UH-60A hovers with its CG 6 m above a flat deck 4 m above the sea
# (bench/shol/ige/), in calm air (--speed-max-kmh 0: no ship-only field is
# needed), two-way coupling with the interaction velocity on the coarse
# grid, at most two coupled iterations, 300 CFD iterations a field.
#
# Checks:
# - the coupled point converged: its trim (trim_status 0 in shol.json) and
#   the coupling (the last iteration's change below 5 %);
# - the collective falls from the free-air trim to the two-way trim by an
#   amount within the band Cheeseman and Bennett's formula gives.
#
# The band. Cheeseman and Bennett (1955; tests/cfd/data/
# cheeseman_bennett_1955.csv, whose rows the script checks against the
# formula it uses): at fixed thrust the induced velocity in ground effect
# is k(z) = 1 - (R / 4 z)^2 of its value out of it. The hub is 0.95 R above
# the deck (z_deck, from the trim's pitch and the aircraft's hub station)
# and 1.44 R above the sea (z_sea). The isolated rotor's field has the sea
# too (the ship's cells open, the sea a wall), so the interaction velocity
# (coupled - isolated) holds the deck's ground effect relative to the
# sea's: the inflow falls by (k(z_sea) - k(z_deck)) v_h, 3.9 % of v_h,
# where the flight model's own inflow has no ground effect. Blade-element
# theory at fixed thrust (uniform inflow, linear twist: C_T/sigma =
# (a/2)(theta_0/3 + theta_tw/4 - lambda/2)) turns that into a collective
# pitch change of 1.5 d(lambda), lambda_h = sqrt(C_T/2) from the trim's
# thrust: about 0.18 deg, 1.1 % of the collective's travel. The check
# passes between 0.5 and 1.25 times that:
# - at most the value of an infinite ground plane (the deck is 2.2 R from
#   the spot each side and 4 m above the sea, so it gives less), plus 25 %
#   for the conversion (the flight model has tip loss and a non-uniform
#   inflow, and the trim also moves the attitudes); this rejects an
#   interaction that takes the whole ground effect relative to free air
#   (1 - k(z_deck), 1.8 times the formula's value: the sea counted in);
# - at least half of it: the finite deck and the coarse grid (the
#   slipstream edge within a cell or two of the tips) take some, not most,
#   of the effect; this rejects no ground effect and the pointwise
#   interaction's wrong sign.
# The free-air collective comes from report.md (0.1 % resolution), the
# two-way one from shol.json.
# Usage: bench/shol/ige_check.sh DISIM [DIR]
set -eu
disim=$1
if [ -n "${2:-}" ]; then
    dir=$2
    mkdir -p "$dir"
else
    dir=$(mktemp -d /tmp/disim_ige_XXXXXX)
    trap 'rm -rf "$dir"' EXIT
fi
here=$(dirname "$0")
ref=$here/../../tests/cfd/data/cheeseman_bennett_1955.csv
aircraft=$here/../../scenarios/aircraft/uh60a.ini
"$disim" shol "$here/ige/flat_ige.ini" --db "$dir/db" -o "$dir/out" --speed-max-kmh 0 \
    --max-coupling-iter 2 --cfd-max-iter 300 > "$dir/run.csv" 2> "$dir/run.log"
fail() { echo "shol_ige: $*"; exit 1; }
# calm air only: no ship-only field was built (couple_trim, cmd_shol)
if ls "$dir/db/fields/" | grep -q shiponly; then
    fail "calm air only built a ship-only field"
fi
# the coupling history rows of the calm-air point:
# | head | 0.0 | iter | thrust kN | coll | long | lat | pedal | roll | pitch | change |
# the coupling history's rows: direction, speed, then the iteration number
# (the bands table's head row has a speed range there)
rows=$(grep -E '^\| head \| 0\.0 \| [0-9]+ \|' "$dir/out/report.md") || fail "no coupling history in report.md"
echo "$rows"
[ "$(echo "$rows" | wc -l)" -ge 2 ] || fail "no coupled iteration"
last=$(echo "$rows" | tail -1)
change=$(echo "$last" | awk -F'|' '{print $12+0}')
awk -v c="$change" 'BEGIN { exit !(c < 5.0) }' || fail "the coupling did not converge (change $change %)"
json=$dir/out/shol.json
[ "$(grep -c '"trim_status": 0' "$json")" -eq 1 ] || fail "the coupled trim did not converge (shol.json)"
two=$(grep '"trim_status": 0' "$json" | grep -o '"collective_pct": [-0-9.e+]*' | awk '{print $2}')
free=$(echo "$rows" | awk -F'|' '$4+0 == 0 {print $6+0}')
thrust_kN=$(echo "$last" | awk -F'|' '{print $5+0}')
pitch_deg=$(echo "$last" | awk -F'|' '{print $11+0}')
cg_m=$(awk -F= '$1 ~ /^hover_height_m/ {print $2+0}' "$here/ige/flat_ige.ini")
deck_m=$(awk -F= '$1 ~ /^deck_height_m/ {print $2+0}' "$here/ige/ships/flat.ini")
echo "calm air: collective free air $free %, two-way $two % (thrust $thrust_kN kN, pitch $pitch_deg deg)"
# the aircraft's main rotor and collective gearing, the band, the check
awk -v free="$free" -v two="$two" -v T="$thrust_kN" -v th="$pitch_deg" -v cg="$cg_m" -v deck="$deck_m" \
    -v ref="$ref" '
    function num(s) { sub(/;.*/, "", s); return s + 0 }
    /^\[/ { sec = $0 }
    sec == "[main_rotor]" && $1 ~ /^radius_m/ { split($0, a, "="); R = num(a[2]) }
    sec == "[main_rotor]" && $1 ~ /^omega_radps/ { split($0, a, "="); Om = num(a[2]) }
    sec == "[main_rotor]" && $1 ~ /^hub_B_m/ { split($0, a, "="); split(a[2], h, ","); hx = num(h[1]); hz = num(h[3]) }
    sec == "[controls]" && $1 ~ /^collective_travel_in/ { split($0, a, "="); trav = num(a[2]) }
    sec == "[controls]" && $1 ~ /^collective_deg_per_in/ { split($0, a, "="); gear = num(a[2]) }
    END {
        pi = atan2(0, -1)
        if (!(R > 0 && Om > 0 && trav > 0 && gear > 0)) { print "shol_ige: aircraft file unread"; exit 1 }
        # the reference: its rows follow the formula used here
        n = 0
        while ((getline line < ref) > 0) {
            if (line ~ /^#/ || line !~ /,/) continue
            split(line, f, ",")
            if ((f[2] - (1 - (1 / (4 * f[1]))^2))^2 > 1e-10) { print "shol_ige: " ref " row " line " is not 1 - (R/4z)^2"; exit 1 }
            n++
        }
        if (n < 3) { print "shol_ige: no rows in " ref; exit 1 }
        t = th * pi / 180
        hub = cg + hx * sin(t) - hz * cos(t)   # hub above the deck (hub_B_m z is down)
        zd = hub / R; zs = (hub + deck) / R
        kd = 1 - (1 / (4 * zd))^2; ks = 1 - (1 / (4 * zs))^2
        CT = T * 1000 / (1.225 * pi * R * R * (Om * R)^2)
        lam = sqrt(CT / 2)
        pct_per_rad = 100 / (trav * gear * pi / 180)
        cb = 1.5 * (ks - kd) * lam * pct_per_rad
        lo = 0.5 * cb; hi = 1.25 * cb
        red = free - two
        printf "Cheeseman and Bennett: hub z/R %.3f over the deck, %.3f over the sea; inflow %.4f and %.4f of v_h, " \
               "interaction %.1f %% of v_h; C_T %.5f; collective reduction %.2f %% of travel (band %.2f-%.2f %%)\n",
               zd, zs, kd, ks, 100 * (ks - kd), CT, cb, lo, hi
        printf "two-way reduction %.2f %% of travel = %.2f of Cheeseman and Bennett\n", red, red / cb
        if (red < lo || red > hi) { print "ground effect: NOT in the band"; exit 1 }
        print "ground effect: in the band"
    }' "$aircraft"
