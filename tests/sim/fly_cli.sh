#!/bin/sh
# disim fly: --fast and --realtime fly the same trajectory (the step has no
# clock; pacing only waits), also with a seaway and turbulence; the CSV is
# complete and nothing is left half-written; bad flags and a sweep without
# the flight's WOD are refused. The gear: --start deck stands on the deck
# with its loads in the CSV; a crash (the automated pilot flown into the
# hangar) ends the run cleanly, named, exit status 3, its CSV written (the
# loop's log at a crash: test_flight); the scenario's [pilot] and [task] fly
# where no flag says.
# Usage: fly_cli.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_fly_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0 pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
args="$src/scenarios/cg47_uh60a.ini --duration 2 --wod-speed-kt 20 --wod-dir-deg -30 --sea-state 4 --ship-speed-kt 10 --db $tmp/db"
"$disim" fly $args --fast --csv "$tmp/fast.csv" 2> "$tmp/fast.log" && ok || { bad "fly --fast failed"; cat "$tmp/fast.log"; }
"$disim" fly $args --realtime --lcm memq:// --csv "$tmp/rt.csv" 2> "$tmp/rt.log" && ok || { bad "fly --realtime failed"; cat "$tmp/rt.log"; }
[ "$(wc -l < "$tmp/fast.csv")" -eq 102 ] && ok || bad "expected a header and 101 rows at 50 Hz over 2 s"
cmp -s "$tmp/fast.csv" "$tmp/rt.csv" && ok || bad "--fast and --realtime flew different trajectories"
grep -q "2.00 s flown in [01]\.[0-9]* s" "$tmp/fast.log" && ok || bad "--fast: no summary, or slower than real time"
grep -q "2.00 s flown in 2\.[0-9]* s (1.0x real time)" "$tmp/rt.log" && ok || { bad "--realtime: not paced at real time"; cat "$tmp/rt.log"; }
# another seed, another seaway: another trajectory
"$disim" fly $args --fast --seed 7 --csv "$tmp/s7.csv" 2> /dev/null && ! cmp -s "$tmp/fast.csv" "$tmp/s7.csv" && ok \
    || bad "--seed 7 flew the same trajectory"
ls "$tmp"/*.tmp* > /dev/null 2>&1 && bad "a temporary CSV was left" || ok
# the scenario's [sea] and [wod] turbulence when no flag overrides them
"$disim" fly "$src/tests/sim/data/sea.ini" --fast --duration 0.5 --db "$tmp/db" 2> "$tmp/sea.log" \
    && grep -q "sea state 4" "$tmp/sea.log" && ok || { bad "the scenario's sea state was not flown"; cat "$tmp/sea.log"; }
"$disim" fly "$src/tests/sim/data/sea.ini" --fast --duration 0.5 --sea-state 2 --db "$tmp/db" 2> "$tmp/sea.log" \
    && grep -q "sea state 2" "$tmp/sea.log" && ok || bad "--sea-state did not override the scenario"
# the airwake from the database: the ship-only field disim shol built is
# flown; a corrupt one never is (its checksum fails: free stream, requested anew)
e2e="$src/tests/couple/sfs2_uh60a.ini"
"$disim" shol "$e2e" --coupling one-way --cfd-max-iter 10 --speed-max-kmh 5 -o "$tmp/shol" --db "$tmp/db2" \
    > /dev/null 2> "$tmp/shol.log" || { bad "disim shol could not build the field"; cat "$tmp/shol.log"; }
"$disim" fly "$e2e" --fast --duration 1 --wod-speed-kt 10 --wod-dir-deg 0 --db "$tmp/db2" --csv "$tmp/f1.csv" 2> "$tmp/f1.log" \
    && grep -q ", airwake field," "$tmp/f1.log" && ok || { bad "the database's field was not flown"; cat "$tmp/f1.log"; }
tail -1 "$tmp/f1.csv" | awk -F, '{exit !($18 == 0)}' && ok || bad "air_flags: expected 0 (the field) at the end"
for f in "$tmp"/db2/fields/*.h5; do printf 'corrupt' | dd of="$f" bs=1 seek=4096 conv=notrunc 2> /dev/null; done
"$disim" fly "$e2e" --fast --duration 1 --wod-speed-kt 10 --wod-dir-deg 0 --db "$tmp/db2" --csv "$tmp/f2.csv" 2> "$tmp/f2.log" \
    && grep -q "free stream until the airwake field is built" "$tmp/f2.log" && ok || { bad "a corrupt field was flown"; cat "$tmp/f2.log"; }
tail -1 "$tmp/f2.csv" | awk -F, '{exit !($18 == 1)}' && ok || bad "air_flags: expected 1 (free stream) with the field corrupt"
ls "$tmp"/db2/queue/*.req > /dev/null 2>&1 && ok || bad "the corrupt field was not requested again"
# the quick level first: with only the quick field in the database the
# flight flies it, asks for the scenario's coarse one (marked as waited
# for while it flies, the mark gone after) and says what it flew
"$disim" airwake "$e2e" --wod-speed-kt 29.16 --wod-dir-deg 0 --rotor off --grid quick --queue "$tmp/db3" > /dev/null 2>&1
"$disim" airwaked "$tmp/db3" --ships "$src/scenarios/ships" --jobs 1 --no-lcm --exit-when-idle --max-iter 10 > "$tmp/db3.log" 2>&1 \
    || { bad "the builder could not build the quick field"; cat "$tmp/db3.log"; }
"$disim" fly "$e2e" --fast --duration 1 --wod-speed-kt 10 --wod-dir-deg 0 --db "$tmp/db3" --csv "$tmp/f3.csv" 2> "$tmp/f3.log" \
    && grep -q "quick airwake field until a finer one is built" "$tmp/f3.log" \
    && grep -q "the airwake flown: quick 0.0-1.0 s (a finer field still to come)" "$tmp/f3.log" && ok \
    || { bad "the quick field was not flown, or not said"; cat "$tmp/f3.log"; }
ls "$tmp"/db3/queue/*_off_coarse_*.req > /dev/null 2>&1 && ok || bad "the coarse field was not requested"
ls "$tmp"/db3/queue/*_off_quick_*.req > /dev/null 2>&1 && bad "the quick field was requested again" || ok
[ -z "$(ls "$tmp/db3/waiting")" ] && ok || bad "a wait mark was left: $(ls "$tmp/db3/waiting")"
# the gear: standing on the deck in sea state 4, the legs carrying the weight
"$disim" fly $args --fast --start deck --csv "$tmp/deck.csv" 2> "$tmp/deck.log" \
    && grep -q "gear: on the deck at the end" "$tmp/deck.log" && ok || { bad "--start deck failed"; cat "$tmp/deck.log"; }
tail -1 "$tmp/deck.csv" | awk -F, '{exit !($21 == 1 && $22 > 60000 && $22 < 90000 && $23 == 0)}' && ok \
    || { bad "--start deck: expected on_deck 1, the legs' load near the weight, no contact flags"; tail -1 "$tmp/deck.csv"; }
# on the deck too, real time and as fast as it can fly the same trajectory
"$disim" fly $args --realtime --lcm memq:// --start deck --csv "$tmp/deck_rt.csv" 2> "$tmp/deck_rt.log" \
    && cmp -s "$tmp/deck.csv" "$tmp/deck_rt.csv" && ok || { bad "--start deck: --fast and --realtime differ"; cat "$tmp/deck_rt.log"; }
tail -1 "$tmp/fast.csv" | awk -F, '{exit !($19 > 60000 && $20 > 5e5 && $21 == 0 && $22 == 0)}' && ok \
    || { bad "hover: expected the rotor's thrust and power, off the deck"; tail -1 "$tmp/fast.csv"; }
# a crash ends the run cleanly: named, exit status 3, the CSV and the log written
hangar="$src/tests/sim/data/into_hangar.ini"
"$disim" fly "$src/scenarios/cg47_uh60a.ini" --wod-speed-kt 0 --wod-dir-deg 0 --db "$tmp/db" --pilot auto --task "$hangar" \
    --csv "$tmp/crash.csv" 2> "$tmp/crash.log"
[ $? -eq 3 ] && grep -q "the flight ended at .*: crash: [a-z_]* hit hangar" "$tmp/crash.log" && [ -s "$tmp/crash.csv" ] && ok \
    || { bad "a crash into the hangar: expected exit status 3 naming it and the CSV"; cat "$tmp/crash.log"; }
tail -1 "$tmp/crash.csv" | awk -F, '{exit !($23 == 4)}' && ok || bad "the crash's last CSV row: expected contact_flags 4"
# the scenario's [pilot] type = auto flies its [task] (headless, as --pilot auto --task)
"$disim" fly "$src/tests/sim/data/pilot_auto.ini" --duration 1 --db "$tmp/db" 2> "$tmp/sc.log" \
    && grep -q "the automated pilot flies .*land_port.ini" "$tmp/sc.log" && ok || { bad "[pilot] type = auto not flown"; cat "$tmp/sc.log"; }
# ... and [pilot] stations, as --stations
"$disim" fly "$src/tests/sim/data/pilot_station.ini" --fast --duration 0.5 --lcm memq:// --db "$tmp/db" 2> "$tmp/st.log" \
    && grep -q "station deck: 0 taken.*station cockpit: 0 taken" "$tmp/st.log" && ok || { bad "[pilot] stations not taken"; cat "$tmp/st.log"; }
"$disim" fly "$src/tests/sim/data/pilot_station.ini" --fast --duration 0.5 --lcm memq:// --stations solo --db "$tmp/db" \
    2> "$tmp/st.log" && grep -q "station solo: 0 taken" "$tmp/st.log" && ! grep -q "station deck" "$tmp/st.log" && ok \
    || { bad "--stations did not override [pilot] stations"; cat "$tmp/st.log"; }
ls "$tmp"/*.tmp* > /dev/null 2>&1 && bad "a temporary file was left" || ok
# refusals: exit status and message, nothing written
"$disim" fly $args --fast --sea-state 9 --csv "$tmp/x.csv" 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "sea-state: expected a whole number in \[0, 6\], got '9'" "$tmp/bad.log" && [ ! -e "$tmp/x.csv" ] && ok \
    || { bad "--sea-state 9 accepted"; cat "$tmp/bad.log"; }
"$disim" fly "$src/scenarios/cg47_uh60a.ini" --fast --duration 1 --db "$tmp/db" 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "a WOD sweep: give the flight's --wod-speed-kt and --wod-dir-deg" "$tmp/bad.log" && ok \
    || { bad "a sweep scenario without the flight's WOD accepted"; cat "$tmp/bad.log"; }
"$disim" fly "$src/scenarios/cg47_uh60a.ini" --rate-hz 5 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "rate-hz: expected a number in \[10, 10000\], got '5'" "$tmp/bad.log" && ok || bad "--rate-hz 5 accepted"
"$disim" fly "$src/scenarios/cg47_uh60a.ini" --wobble 2> "$tmp/bad.log"
[ $? -eq 2 ] && ok || bad "an unknown flag: expected exit status 2"
"$disim" fly $args --fast --start deck --no-gear 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q -- "--start deck: not with --no-gear" "$tmp/bad.log" && ok || { bad "--start deck --no-gear accepted"; cat "$tmp/bad.log"; }
echo "fly_cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
