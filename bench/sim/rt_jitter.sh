#!/bin/sh
# The flight loop in real time beside the airwake builder: disim fly at
# 200 Hz for DURATION seconds (600 by default) while disim airwaked builds
# a CG-47 default-grid field on both cores. Prints the loop's summary:
# overruns, step-time percentiles and how late the wake-ups came after
# their deadlines (the jitter), and what the system granted (SCHED_FIFO,
# locked memory). It also samples the cores' steal time (/proc/stat: the
# time a virtual machine's vCPU was runnable but not run by the host) every
# 0.1 s and prints the intervals in which any was stolen: a wake-up late by
# milliseconds under SCHED_FIFO on an otherwise preemptible kernel is the
# host not running the vCPU. Usage: bench/sim/rt_jitter.sh [--render [HZ]]
# [DISIM] [DURATION] from the source root.
#
# --render [HZ]: the loop beside live rendering instead of the builder:
# the same flight twice, without rendering and then with the deck camera
# drawn live at 640 x 480, HZ frames a second (10 by default) into a
# temporary folder (disim fly --render), each run's summary printed, so the
# loop's step p99 and overruns with the renderer stand beside those without.
set -u
render=
if [ "${1:-}" = --render ]; then
    shift
    render=10
    case "${1:-}" in [0-9]*) render=$1; shift ;; esac
fi
disim=${1:-./build/app/disim} dur=${2:-600}
tmp=$(mktemp -d /tmp/disim_rt_XXXXXX)
spid= bpid=
trap 'kill $bpid $spid 2> /dev/null; [ -n "$bpid" ] && wait "$bpid" 2> /dev/null; rm -rf "$tmp"' EXIT
"$disim" airwake scenarios/cg47_uh60a.ini --wod-speed-kt 29.16 --wod-dir-deg -30 --rotor off --grid default \
    --queue "$tmp/db" > /dev/null 2>&1
if [ -z "$render" ]; then
    "$disim" airwaked "$tmp/db" --jobs 2 --no-lcm > "$tmp/builder.log" 2>&1 &
    bpid=$!
    sleep 5
    echo "rt_jitter: builder pid $bpid on $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
else
    echo "rt_jitter: no builder; the loop alone, then beside live rendering at $render Hz, on $(nproc) cores"
fi
# steal sampler: one line "t_s steal_ticks" per 0.1 s (cpu line, field 9)
(while :; do
    printf '%s %s\n' "$(cut -d' ' -f1 /proc/uptime)" "$(awk '/^cpu /{print $9; exit}' /proc/stat)"
    sleep 0.1
done) > "$tmp/steal.txt" &
spid=$!
fly() { # LINES [FLAGS]: the run's last LINES lines of summary
    n=$1
    shift
    "$disim" fly scenarios/cg47_uh60a.ini --realtime --no-lcm --duration "$dur" --wod-speed-kt 20 --wod-dir-deg -30 \
        --sea-state 4 --db "$tmp/db" "$@" 2>&1 | grep -v '^\r' | tail -"$n"
}
if [ -z "$render" ]; then
    fly 4
else
    echo "rt_jitter: without rendering"
    fly 4
    echo "rt_jitter: with the deck camera at 640x480, $render Hz"
    fly 5 --render "$tmp/frames" --render-rate "$render" --render-size 640x480 --render-cameras deck
    echo "rt_jitter: $(ls "$tmp/frames" 2> /dev/null | wc -l) frames written"
fi
kill "$spid" 2> /dev/null
awk -v hz="$(getconf CLK_TCK)" 'NR > 1 && $2 > prev { n++; ms += ($2 - prev) * 1000 / hz }
    { prev = $2; last = $1; if (NR == 1) first = $1 }
    END { printf "rt_jitter: steal: %.0f ms over %.0f s, in %d of %d 0.1 s intervals\n", ms, last - first, n, NR - 1 }' \
    "$tmp/steal.txt"
if [ -z "$render" ]; then
    echo "rt_jitter: load at the end $(cut -d' ' -f1-3 /proc/loadavg); builder: $(tail -1 "$tmp/builder.log" | cut -c1-120)"
else
    echo "rt_jitter: load at the end $(cut -d' ' -f1-3 /proc/loadavg)"
fi
