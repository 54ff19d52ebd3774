#!/bin/sh
# disim shol's status line while it waits for the builder it started (in
# another process): on a terminal one line rewritten in place (\r) with the
# time waited, the field's iteration of the cap, percent, residual and time
# left, and the database's fields ready and queued; in a log no \r and no
# status line, only the one "waiting for airwake" line per field.
# usage: airwake_wait_tty.sh DISIM SRC_DIR
disim=$1
src=$2
. "$src/tests/skip.sh"
command -v script > /dev/null || skip airwake_wait_tty "no script(1) (util-linux) to give it a terminal"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
cr=$(printf '\r')
scen="$src/tests/couple/sfs2_uh60a.ini"
# the width the line is cut to: fixed, whatever terminal runs the test
COLUMNS=200 script -qc "\"$disim\" shol \"$scen\" --coupling one-way --cfd-max-iter 40 -o \"$tmp/out-tty\" --db \"$tmp/tty\"" \
    /dev/null > "$tmp/tty.out" 2>&1
grep -q "^0.0,[0-9.]*,[a-z]*" "$tmp/tty.out" || { echo "terminal run: no envelope"; tail -5 "$tmp/tty.out"; fail=1; }
# the status lines, one per \r, without the clear
tr '\r' '\n' < "$tmp/tty.out" | sed 's/\x1b\[K//g' | grep -a "^waited " > "$tmp/status"
pat="^waited [0-9]* s | it [0-9]*/40 [0-9]* %, res [0-9.]*e[-+][0-9]*\(, <= [0-9]* s left\)\? | 0 ready, 0 queued | SFS2_shiponly_v15.00_d+000.00_off_coarse\$"
n=$(grep -c "$pat" "$tmp/status")
nleft=$(grep "$pat" "$tmp/status" | grep -c "<= [0-9]* s left")
[ "$n" -ge 2 ] && [ "$nleft" -ge 1 ] || { echo "terminal: $n status lines with iteration, percent, residual and the database," \
    "$nleft with the time left (expected 2 or more, and 1 or more):"; tail -5 "$tmp/status"; fail=1; }
# rewritten in place: each status line starts with \r and a clear, none with a newline of its own
grep -a "waited [0-9]* s |" "$tmp/tty.out" | grep -qv "$cr" && { echo "terminal: a status line without \\r"; fail=1; }
COLUMNS=200 "$disim" shol "$scen" --coupling one-way --cfd-max-iter 40 -o "$tmp/out-log" --db "$tmp/log" \
    > "$tmp/log.csv" 2> "$tmp/log.err" || { echo "log run failed"; cat "$tmp/log.err"; fail=1; }
grep -q "$cr" "$tmp/log.err" && { echo "log: carriage returns:"; cat -A "$tmp/log.err" | head; fail=1; }
grep -q "waited [0-9]" "$tmp/log.err" && { echo "log: status lines:"; grep "waited" "$tmp/log.err" | head -3; fail=1; }
w=$(grep -c "waiting for airwake SFS2_shiponly" "$tmp/log.err")
[ "$w" -eq 1 ] || { echo "log: $w 'waiting for airwake' lines (expected 1)"; cat "$tmp/log.err"; fail=1; }
cmp -s "$tmp/out-tty/shol.csv" "$tmp/out-log/shol.csv" || { echo "the terminal and log runs gave different envelopes"; fail=1; }
exit $fail
