#!/bin/sh
# run.sh BUILD_DIR SECONDS CORPUS_DIR [HARNESS...] -- run each libFuzzer
# harness of BUILD_DIR (built with -DDISIM_FUZZ=ON; all of them when none
# is named, e.g. fuzz_ini fuzz_field) for SECONDS, one after another, from
# the source root (the schema harnesses read scenarios/). The seed corpora
# are made first (seeds.sh) into CORPUS_DIR/seeds; each harness keeps what
# it finds in CORPUS_DIR/<harness>, its log in CORPUS_DIR/logs/<harness>.log
# and any failing input in CORPUS_DIR/artifacts/. A run stops at SECONDS
# or at FUZZ_RUNS executions (default 10,000,000). Prints each harness's
# final figures (executions, time, executions a second, coverage); exits 1
# when a harness found a crash, a hang (an input over FUZZ_TIMEOUT s,
# default 20), a leak, a sanitizer report or ran out of memory (2 GB).
# FUZZ_ARGS adds libFuzzer options, e.g. "-fork=1 -ignore_crashes=1" to go
# on past crashes (each input kept in artifacts/) where a third-party
# library's own bugs stop a run.
# fuzz_field drives libhdf5 1.10.8, whose own defects on corrupt files (a
# use after free and a read past a buffer in H5Aexists, an allocation of
# 2 GB that a damaged superblock asks for in H5Fopen: docs/validation.md,
# Fuzzing) stop a run within seconds: it runs in fork mode past crashes,
# hangs and running out of memory, and each input kept is then run alone
# and classed by its report's innermost frame that is either disim's or
# libhdf5's (the sanitizer's, libFuzzer's, the allocators' and other
# libraries' frames, libc's and zlib's, left out): libhdf5's, the
# library's own (counted, kept); disim's, or no frame to tell, fails the
# run. Fork mode's own exit status is that of its last job,
# crashed or not: what the inputs kept say decides. A disim defect that
# shows first inside libhdf5 would be classed as the library's: the cost
# of going on.
set -eu
[ $# -ge 3 ] || { echo "usage: run.sh BUILD_DIR SECONDS CORPUS_DIR [HARNESS...]" >&2; exit 2; }
build=$(cd "$1" && pwd)
secs=$2
mkdir -p "$3"
corpus=$(cd "$3" && pwd)
shift 3
cd "$(dirname "$0")/../.."
src=$(pwd)
if [ $# -eq 0 ]; then
    set -- $(cd "$build/tests/fuzz" && ls fuzz_* | grep -v '^fuzz_seeds$' | sort)
fi
sh "$src/tests/fuzz/seeds.sh" "$build" "$corpus/seeds" > /dev/null
mkdir -p "$corpus/logs" "$corpus/artifacts"
failed=""
# innermost LOG BIN LIB: the innermost frame of the report in LOG that is
# disim's (in BIN, or a source file of this tree) or LIB's, leaving out the
# sanitizer's, libFuzzer's and the allocators' frames and every other
# library's (libc's, zlib's, the signal trampoline): which of disim and LIB
# is nearest the fault
innermost() {
    sed -n '/ERROR\|runtime error\|ALARM/,$p' "$1" | grep '^ *#[0-9]' |
        grep -v -E ' in (fuzzer::|__sanitizer|__asan|__lsan|__ubsan|__interceptor_|(malloc|calloc|realloc|free|operator new) )' |
        grep -F -e "$src/" -e "$2+" -e "$3" | head -1
}
printf '%-22s %12s %8s %9s %7s %7s  %s\n' harness executions time_s exec/s cov ft result
for h in "$@"; do
    bin="$build/tests/fuzz/$h"
    seeds="$corpus/seeds/${h#fuzz_}"
    [ -x "$bin" ] || { echo "run.sh: $bin not built" >&2; exit 2; }
    [ -d "$seeds" ] || { echo "run.sh: no seeds for $h ($seeds)" >&2; exit 2; }
    mkdir -p "$corpus/$h"
    log="$corpus/logs/$h.log"
    lib=""
    [ "$h" = fuzz_field ] && lib=libhdf5
    fork=""
    [ -n "$lib" ] && fork="-fork=1 -ignore_crashes=1"
    before=$(ls "$corpus/artifacts" | grep "^$h-" || true)
    t0=$(date +%s)
    rc=0
    "$bin" -max_total_time="$secs" -runs="${FUZZ_RUNS:-10000000}" -timeout="${FUZZ_TIMEOUT:-20}" \
        -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$corpus/artifacts/$h-" $fork ${FUZZ_ARGS:-} \
        "$corpus/$h" "$seeds" > "$log" 2>&1 || rc=$?
    libs=0
    if [ -n "$lib" ]; then
        # fork mode exits with its last job's status, crashed or not
        grep -q '^INFO: exiting: ' "$log" && rc=0
        for a in $(ls "$corpus/artifacts" | grep "^$h-" || true); do
            echo "$before" | grep -qx "$a" && continue
            case "$a" in
            "$h"-crash-* | "$h"-leak-* | "$h"-oom-* | "$h"-timeout-*) ;;
            *) echo "run.sh: $h: $a (not an input libFuzzer keeps)" >> "$log"; rc=1; continue ;;
            esac
            alone="$corpus/logs/$a.log"
            "$bin" -timeout="${FUZZ_TIMEOUT:-20}" -rss_limit_mb=2048 "$corpus/artifacts/$a" > "$alone" 2>&1 && continue
            if innermost "$alone" "$bin" "$lib" | grep -q "$lib"; then
                libs=$((libs + 1))
            else
                echo "run.sh: $h: $a stopped outside $lib, see $alone" >> "$log"
                rc=1
            fi
        done
    fi
    t1=$(date +%s)
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    last=$(grep -E '^#[0-9]+' "$log" | tail -1)
    # fork mode prints no final figures: its last line of progress has them
    [ -n "$execs" ] || execs=$(echo "$last" | sed -n 's/^#\([0-9]*\):.*/\1/p')
    cov=$(echo "$last" | sed -n 's/.* cov: \([0-9]*\).*/\1/p')
    ft=$(echo "$last" | sed -n 's/.* ft: \([0-9]*\).*/\1/p')
    el=$((t1 - t0))
    [ "$el" -gt 0 ] || el=1
    result=ok
    [ "$libs" -gt 0 ] && result="ok ($libs inputs stopped in $lib's own code, kept in artifacts/)"
    if [ "$rc" -ne 0 ]; then
        result="FAILED (exit $rc): $(grep -m1 -E 'run.sh:|ERROR|SUMMARY|deadly|timeout' "$log" || true), see $log"
        failed="$failed $h"
    fi
    printf '%-22s %12s %8s %9s %7s %7s  %s\n' "$h" "${execs:-?}" "$el" "$(( ${execs:-0} / el ))" "${cov:-?}" \
        "${ft:-?}" "$result"
done
if [ -n "$failed" ]; then
    echo "run.sh: failed:$failed (inputs in $corpus/artifacts)" >&2
    exit 1
fi
