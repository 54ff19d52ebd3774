#!/bin/sh
# bench_shol.sh -- the SHOL benchmarks (not in ctest):
#   1. a whole candidate envelope from an empty airwake database (every
#      field built by the background builder, `--jobs` builds at once);
#   2. the same command again on the now full database (the baseline of
#      "rerun within 10 s"): no field is built, only trims.
# It prints both wall times, the fields built, the trims and the ratio.
# Usage: bench/shol/bench_shol.sh DISIM SCENARIO [--grid G] [--coupling C] [--domain whole|zone] [--jobs N]
#        [--cfd-max-iter N] [--keep DIR]
#   e.g. bench/shol/bench_shol.sh build/app/disim scenarios/cg47_uh60a.ini --grid coarse
set -u
[ $# -ge 2 ] || { echo "usage: $0 DISIM SCENARIO [--grid G] [--coupling C] [--jobs N] [--keep DIR]" >&2; exit 2; }
disim=$1 scen=$2
shift 2
grid="" coupling="" domain="" jobs=$(nproc) keep="" maxit=""
while [ $# -gt 0 ]; do
    case "$1" in
    --grid) grid="--grid $2"; shift 2 ;;
    --coupling) coupling="--coupling $2"; shift 2 ;;
    --domain) domain="--domain $2"; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --keep) keep=$2; shift 2 ;;
    --cfd-max-iter) maxit="--max-iter $2"; shift 2 ;;
    *) echo "$0: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
if [ -n "$keep" ]; then
    tmp=$keep
    mkdir -p "$tmp" || exit 1
else
    tmp=$(mktemp -d /tmp/bench_shol_XXXXXX)
fi
ships=$(dirname "$scen")/ships
now() { date +%s.%N; }
# The builder is started here so that its number of jobs is known.
"$disim" airwaked "$tmp/db" --jobs "$jobs" --ships "$ships" --no-lcm $maxit > "$tmp/builder.out" 2>&1 &
bpid=$!
sleep 1
t0=$(now)
"$disim" shol "$scen" $grid $coupling $domain -o "$tmp/out1" --db "$tmp/db" > "$tmp/run1.csv" 2> "$tmp/run1.log"
rc1=$?
t1=$(now)
kill "$bpid" 2>/dev/null
wait "$bpid" 2>/dev/null
nf=$(ls "$tmp/db/fields/"*.h5 2>/dev/null | wc -l)
t2=$(now)
"$disim" shol "$scen" $grid $coupling $domain -o "$tmp/out2" --db "$tmp/db" > "$tmp/run2.csv" 2> "$tmp/run2.log"
rc2=$?
t3=$(now)
same=no
cmp -s "$tmp/run1.csv" "$tmp/run2.csv" && same=yes
started=no
grep -q "started an airwake builder" "$tmp/run2.log" && started=yes
awk -v a="$t0" -v b="$t1" -v c="$t2" -v d="$t3" -v nf="$nf" -v j="$jobs" -v rc1="$rc1" -v rc2="$rc2" \
    -v same="$same" -v started="$started" -v scen="$scen" -v maxit="$maxit" 'BEGIN {
    full = b - a; re = d - c;
    printf("scenario %s, %d builder job(s), %s\n", scen, j, maxit == "" ? "CFD iteration limit: the solver default" : maxit);
    printf("envelope from an empty database: %.1f s (%.1f min), exit %d, %d fields built\n", full, full / 60, rc1, nf);
    printf("rerun on the full database:      %.2f s, exit %d, same envelope: %s, builder started: %s\n", re, rc2, same, started);
    printf("ratio full / rerun: %.0f\n", re > 0 ? full / re : 0);
}'
echo "envelope (run 1):"
cat "$tmp/run1.csv"
[ -n "$keep" ] || rm -rf "$tmp"
[ "$rc1" -eq 0 ] && [ "$rc2" -eq 0 ]
