#!/bin/sh
# Inputs that are not what they claim, refused at once with a non-zero exit
# and nothing written: disim fly --replay-inputs LOG with an event whose
# data length is 0x7FFFFFFF, /bin/ls, a folder, an empty file, 200 MB of
# zeros, a truncated log, a misframed log (5 bytes slipped in after its
# first event), a log with no pilot_input_t or sim_control_t, /dev/zero
# (no OUT.csv, OUT.lcm or OUT.*.tmp* left); and /dev/zero as the path that
# disim check, fly, shol and station --script read (each would read it for
# ever). Every run is under a timeout: a hang fails, it is not waited out.
# Usage: fly_bad_inputs.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_bad_inputs_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0 pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
scen="$src/scenarios/cg47_uh60a.ini"
calm="--wod-speed-kt 0 --wod-dir-deg 0 --db $tmp/db"
# a good log with a station's inputs (the automated pilot's, station "auto")
"$disim" fly "$scen" $calm --duration 1 --pilot auto --task "$src/scenarios/tasks/land_port.ini" \
    --log "$tmp/good.lcm" 2> "$tmp/good.err" && [ -s "$tmp/good.lcm" ] && ok \
    || { bad "the good log was not written"; cat "$tmp/good.err"; }
mkdir -p "$tmp/o"
timeout -k 5 60 "$disim" fly "$scen" $calm --fast --no-lcm --duration 0.5 --replay-inputs "$tmp/good.lcm" \
    --csv "$tmp/o/good.csv" 2> "$tmp/replay.err" && [ -s "$tmp/o/good.csv" ] && ok \
    || { bad "the good log's inputs were not replayed"; cat "$tmp/replay.err"; }
rm -f "$tmp/o/good.csv"
# the bad logs
printf '\355\241\332\001\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\021\177\377\377\377DISIM_PILOT_INPUTabcdefgh' \
    > "$tmp/huge_len.lcm"
: > "$tmp/empty.lcm"
truncate -s 200M "$tmp/zeros.lcm"
size=$(wc -c < "$tmp/good.lcm")
head -c $((size - 7)) "$tmp/good.lcm" > "$tmp/truncated.lcm"
set -- $(od -An -tu1 -j20 -N8 "$tmp/good.lcm")
first=$((28 + ($1 << 24 | $2 << 16 | $3 << 8 | $4) + ($5 << 24 | $6 << 16 | $7 << 8 | $8)))
{ head -c "$first" "$tmp/good.lcm"; printf 'junk!'; tail -c +$((first + 1)) "$tmp/good.lcm"; } > "$tmp/misframed.lcm"
"$disim" fly "$scen" $calm --fast --no-lcm --duration 0.2 --log "$tmp/no_inputs.lcm" 2> /dev/null \
    && [ -s "$tmp/no_inputs.lcm" ] || bad "the log without inputs was not written"
mkdir "$tmp/folder.lcm"
for log in "$tmp/huge_len.lcm" /bin/ls "$tmp/folder.lcm" "$tmp/empty.lcm" "$tmp/zeros.lcm" "$tmp/truncated.lcm" \
    "$tmp/misframed.lcm" "$tmp/no_inputs.lcm" /dev/zero; do
    timeout -k 5 30 "$disim" fly "$scen" $calm --fast --no-lcm --duration 1 --replay-inputs "$log" \
        --csv "$tmp/o/OUT.csv" --log "$tmp/o/OUT.lcm" > /dev/null 2> "$tmp/err"
    rc=$?
    { [ "$rc" -ne 0 ] && [ "$rc" -lt 124 ] && grep -q "$log" "$tmp/err"; } && ok \
        || { bad "--replay-inputs $log: exit $rc, expected a refusal naming it"; cat "$tmp/err"; }
    [ -z "$(ls -A "$tmp/o")" ] && ok || { bad "--replay-inputs $log: left $(ls -A "$tmp/o")"; rm -f "$tmp"/o/*; }
done
timeout -k 5 30 "$disim" fly "$scen" $calm --fast --no-lcm --duration 1 --replay-inputs "$tmp/huge_len.lcm" 2> "$tmp/err"
grep -q "2147483664 bytes of channel and data" "$tmp/err" && ok \
    || { bad "0x7FFFFFFF: expected the sizes said without overflow"; cat "$tmp/err"; }
# /dev/zero wherever a path is read: refused at once, saying what it is
for cmd in "check /dev/zero" "fly /dev/zero --fast --no-lcm --duration 1" "shol /dev/zero -o $tmp/shol" \
    "station --script /dev/zero --lcm memq://"; do
    timeout -k 5 30 "$disim" $cmd > /dev/null 2> "$tmp/err" < /dev/null
    rc=$?
    { [ "$rc" -ne 0 ] && [ "$rc" -lt 124 ] && grep -q "/dev/zero: a character device" "$tmp/err"; } && ok \
        || { bad "disim $cmd: exit $rc, expected a refusal (a character device)"; cat "$tmp/err"; }
done
[ ! -e "$tmp/shol" ] && ok || bad "shol /dev/zero: its output folder was made"
echo "fly_bad_inputs: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
