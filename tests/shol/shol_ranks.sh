#!/bin/sh
# disim shol spread over ranks gives the serial envelope bit for bit: a
# small one-way sweep (SFS2 + UH-60A, five directions to 100 km/h, its
# fields built by the serial run with 10 CFD iterations each) run serially,
# by hand with --rank/--ranks (two processes), and under mpirun -np 2 and
# -np 7 (more ranks than directions) over the same database; shol.csv and
# the table on stdout must be the same bytes, shol.json the same but for
# its wall time (a trim warm-started across directions shows there: the
# attribution's ninth digits move with the order the directions are swept
# in); the stage folder is gone after each run. A rank that
# fails, a part of another run and a rank that never comes each stop rank
# 0 with an error naming the rank. Skips (77) without mpirun, after the
# checks that need none.
# Usage: shol_ranks.sh DISIM SOURCE_DIR
set -u
. "$(dirname "$0")/../skip.sh"
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_shol_ranks_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0
scen=$src/tests/shol/data/ranks_sfs2.ini
now() { date +%s.%N; }
same() { # NAME DIR STDOUT: the outputs of DIR against the serial run's
    cmp -s "$tmp/s/shol.csv" "$2/shol.csv" || { echo "$1: shol.csv differs from the serial run's"; diff "$tmp/s/shol.csv" "$2/shol.csv" | head; fail=1; }
    cmp -s "$tmp/s.out" "$3" || { echo "$1: stdout differs from the serial run's"; fail=1; }
    grep -v '"wall_s"' "$tmp/s/shol.json" > "$tmp/a.json"
    grep -v '"wall_s"' "$2/shol.json" > "$tmp/b.json" 2> /dev/null
    cmp -s "$tmp/a.json" "$tmp/b.json" || { echo "$1: shol.json differs from the serial run's"; fail=1; }
    [ -z "$(ls -A "$2" | grep '^\.shol-ranks')" ] || { echo "$1: the stage folder was left behind"; ls -A "$2"; fail=1; }
}
t0=$(now)
"$disim" shol "$scen" --cfd-max-iter 10 -o "$tmp/s" --db "$tmp/db" > "$tmp/s.out" 2> "$tmp/s.err" \
    || { echo "the serial run failed"; cat "$tmp/s.err"; exit 1; }
t1=$(now)
# the serial run again over the built fields: the time to compare with
"$disim" shol "$scen" -o "$tmp/s2" --db "$tmp/db" > "$tmp/s2.out" 2> "$tmp/s2.err" \
    || { echo "the second serial run failed"; cat "$tmp/s2.err"; exit 1; }
t2=$(now)
[ "$(grep -c ',pedal$\|,roll$' "$tmp/s.out")" -ge 2 ] || { echo "expected limited directions"; cat "$tmp/s.out"; fail=1; }
same "serial again" "$tmp/s2" "$tmp/s2.out"

# by hand: two processes, --rank R --ranks 2 (no launcher)
"$disim" shol "$scen" -o "$tmp/h" --db "$tmp/db" --rank 1 --ranks 2 > "$tmp/h1.out" 2> "$tmp/h1.err" &
p1=$!
"$disim" shol "$scen" -o "$tmp/h" --db "$tmp/db" --rank 0 --ranks 2 > "$tmp/h.out" 2> "$tmp/h.err" \
    || { echo "--rank 0 --ranks 2 failed"; cat "$tmp/h.err"; fail=1; }
wait $p1 || { echo "--rank 1 --ranks 2 failed"; cat "$tmp/h1.err"; fail=1; }
[ ! -s "$tmp/h1.out" ] || { echo "rank 1 printed a table"; fail=1; }
grep -q "rank 1 of 2: 2 directions, its part in" "$tmp/h1.err" || { echo "rank 1 did not say what it did"; cat "$tmp/h1.err"; fail=1; }
same "--rank/--ranks" "$tmp/h" "$tmp/h.out"

# rank 0's errors name the rank: a failed one, one of another run, one that never comes
"$disim" shol "$scen" -o "$tmp/x" --db "$tmp/db" --rank 1 --ranks 2 --speed-max-kmh 50 > /dev/null 2> "$tmp/x1.err"
"$disim" shol "$scen" -o "$tmp/x" --db "$tmp/db" --rank 0 --ranks 2 --rank-wait-s 5 > /dev/null 2> "$tmp/x.err"
[ $? -eq 1 ] && grep -q "part-1: a part of another run (rank 1 of 2, other settings)" "$tmp/x.err" \
    || { echo "a part of another run was not refused"; cat "$tmp/x.err"; fail=1; }
"$disim" shol "$scen" -o "$tmp/w" --db "$tmp/db" --rank 0 --ranks 3 --rank-wait-s 2 > /dev/null 2> "$tmp/w.err"
[ $? -eq 1 ] && grep -q "rank 1 of 3: no part in .* within the wait" "$tmp/w.err" \
    || { echo "a missing rank was not named"; cat "$tmp/w.err"; fail=1; }
# a rank that fails leaves its mark: rank 0 stops at once with its error
mkdir -p "$tmp/e"
: > "$tmp/notadir"
"$disim" shol "$scen" -o "$tmp/e" --db "$tmp/notadir/db" --rank 1 --ranks 2 > /dev/null 2> "$tmp/e1.err"
[ $? -eq 1 ] || { echo "rank 1 with a bad database did not fail"; cat "$tmp/e1.err"; fail=1; }
"$disim" shol "$scen" -o "$tmp/e" --db "$tmp/db" --rank 0 --ranks 2 --rank-wait-s 600 > /dev/null 2> "$tmp/e.err"
[ $? -eq 1 ] && grep -q "rank 1 of 2 failed: .*notadir" "$tmp/e.err" \
    || { echo "rank 0 did not name the failed rank"; cat "$tmp/e.err"; fail=1; }
# flags that do not go together
"$disim" shol "$scen" --rank 1 > /dev/null 2> "$tmp/bad.err"
[ $? -eq 2 ] && grep -q "rank R and --ranks N go together" "$tmp/bad.err" || { echo "--rank without --ranks accepted"; fail=1; }
"$disim" shol "$scen" --rank 2 --ranks 2 > /dev/null 2> "$tmp/bad.err"
[ $? -eq 2 ] || { echo "--rank 2 --ranks 2 accepted"; fail=1; }

command -v mpirun > /dev/null 2>&1 || { [ $fail -eq 0 ] || exit 1; skip shol_ranks "no mpirun (Open MPI: apt-get install openmpi-bin)"; }
root=
[ "$(id -u)" -ne 0 ] || root=--allow-run-as-root
t3=$(now)
mpirun $root --oversubscribe -np 2 "$disim" shol "$scen" -o "$tmp/m" --db "$tmp/db" > "$tmp/m.out" 2> "$tmp/m.err" \
    || { echo "mpirun -np 2 failed"; cat "$tmp/m.err"; fail=1; }
t4=$(now)
grep -q "rank 1 of 2: 2 directions" "$tmp/m.err" || { echo "mpirun -np 2: rank 1 did not take its share"; cat "$tmp/m.err"; fail=1; }
same "mpirun -np 2" "$tmp/m" "$tmp/m.out"
mpirun $root --oversubscribe -np 7 "$disim" shol "$scen" -o "$tmp/m7" --db "$tmp/db" > "$tmp/m7.out" 2> "$tmp/m7.err" \
    || { echo "mpirun -np 7 failed"; cat "$tmp/m7.err"; fail=1; }
same "mpirun -np 7" "$tmp/m7" "$tmp/m7.out"
awk -v a="$t0" -v b="$t1" -v c="$t2" -v d="$t3" -v e="$t4" 'BEGIN { printf "serial with its field builds %.1f s, serial over the built fields %.1f s, mpirun -np 2 %.1f s\n", b - a, c - b, e - d }'
[ $fail -eq 0 ] && echo "shol_ranks: ok"
exit $fail
