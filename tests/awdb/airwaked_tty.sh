#!/bin/sh
# disim airwaked's progress: on a terminal one updating line with percent,
# rate and time left; in a log (not a terminal) state changes only.
# usage: airwaked_tty.sh DISIM SRC_DIR
disim=$1
src=$2
. "$src/tests/skip.sh"
command -v script > /dev/null || skip airwaked_tty "no script(1) (util-linux) to give it a terminal"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
queue() {
    "$disim" airwake "$src/tests/couple/sfs2_uh60a.ini" --wod-speed-kt "$1" --rotor off --grid coarse \
        --queue "$tmp/$2" > /dev/null 2>&1 || { echo "queue $2 failed"; exit 1; }
}
queue 20 tty
queue 20 log
script -qc "\"$disim\" airwaked \"$tmp/tty\" --jobs 1 --max-iter 20 --no-lcm --exit-when-idle --ships \"$src/scenarios/ships\"" \
    /dev/null > "$tmp/tty.out" 2>&1
tr '\r' '\n' < "$tmp/tty.out" | grep -q "%  residual .* iteration [0-9]*  [0-9.]* it/s  at most [0-9]* \(s\|min\) left" \
    || { echo "no progress line with rate and time left on a terminal:"; tr '\r' '\n' < "$tmp/tty.out" | tail -5; fail=1; }
grep -q "ready SFS2" "$tmp/tty.out" || { echo "terminal run: field not ready"; fail=1; }
"$disim" airwaked "$tmp/log" --jobs 1 --max-iter 20 --no-lcm --exit-when-idle --ships "$src/scenarios/ships" \
    > "$tmp/log.out" 2>&1
grep -q "ready SFS2" "$tmp/log.out" || { echo "log run: field not ready"; cat "$tmp/log.out"; fail=1; }
grep -q "it/s\|$(printf '\r')" "$tmp/log.out" && { echo "progress lines in a log:"; cat "$tmp/log.out"; fail=1; }
exit $fail
