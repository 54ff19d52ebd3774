#!/bin/sh
# The flight loop in real time beside the airwake builder: disim fly at
# 200 Hz for DURATION seconds (600 by default) while disim airwaked builds
# a CG-47 default-grid field on both cores. Prints the loop's summary:
# overruns, step-time percentiles and how late the wake-ups came after
# their deadlines (the jitter), and what the system granted (SCHED_FIFO,
# locked memory). Usage: bench/sim/rt_jitter.sh [DISIM] [DURATION]
# from the source root.
set -u
disim=${1:-./build/app/disim} dur=${2:-600}
tmp=$(mktemp -d /tmp/disim_rt_XXXXXX)
trap 'kill "$bpid" 2> /dev/null; wait "$bpid" 2> /dev/null; rm -rf "$tmp"' EXIT
"$disim" airwake scenarios/cg47_uh60a.ini --wod-speed-kt 29.16 --wod-dir-deg -30 --rotor off --grid default \
    --queue "$tmp/db" > /dev/null 2>&1
"$disim" airwaked "$tmp/db" --jobs 2 --no-lcm > "$tmp/builder.log" 2>&1 &
bpid=$!
sleep 5
grep -q . "$tmp/builder.log" || true
echo "rt_jitter: builder pid $bpid on $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
"$disim" fly scenarios/cg47_uh60a.ini --realtime --no-lcm --duration "$dur" --wod-speed-kt 20 --wod-dir-deg -30 \
    --sea-state 4 --db "$tmp/db" 2>&1 | grep -v '^\r' | tail -4
echo "rt_jitter: load at the end $(cut -d' ' -f1-3 /proc/loadavg); builder: $(tail -1 "$tmp/builder.log" | cut -c1-120)"
