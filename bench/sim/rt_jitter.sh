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
# host not running the vCPU. Usage: bench/sim/rt_jitter.sh [DISIM]
# [DURATION] from the source root.
set -u
disim=${1:-./build/app/disim} dur=${2:-600}
tmp=$(mktemp -d /tmp/disim_rt_XXXXXX)
spid=
trap 'kill "$bpid" $spid 2> /dev/null; wait "$bpid" 2> /dev/null; rm -rf "$tmp"' EXIT
"$disim" airwake scenarios/cg47_uh60a.ini --wod-speed-kt 29.16 --wod-dir-deg -30 --rotor off --grid default \
    --queue "$tmp/db" > /dev/null 2>&1
"$disim" airwaked "$tmp/db" --jobs 2 --no-lcm > "$tmp/builder.log" 2>&1 &
bpid=$!
sleep 5
grep -q . "$tmp/builder.log" || true
echo "rt_jitter: builder pid $bpid on $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
# steal sampler: one line "t_s steal_ticks" per 0.1 s (cpu line, field 9)
(while :; do
    printf '%s %s\n' "$(cut -d' ' -f1 /proc/uptime)" "$(awk '/^cpu /{print $9; exit}' /proc/stat)"
    sleep 0.1
done) > "$tmp/steal.txt" &
spid=$!
"$disim" fly scenarios/cg47_uh60a.ini --realtime --no-lcm --duration "$dur" --wod-speed-kt 20 --wod-dir-deg -30 \
    --sea-state 4 --db "$tmp/db" 2>&1 | grep -v '^\r' | tail -4
kill "$spid" 2> /dev/null
awk -v hz="$(getconf CLK_TCK)" 'NR > 1 && $2 > prev { n++; ms += ($2 - prev) * 1000 / hz }
    { prev = $2; last = $1; if (NR == 1) first = $1 }
    END { printf "rt_jitter: steal: %.0f ms over %.0f s, in %d of %d 0.1 s intervals\n", ms, last - first, n, NR - 1 }' \
    "$tmp/steal.txt"
echo "rt_jitter: load at the end $(cut -d' ' -f1-3 /proc/loadavg); builder: $(tail -1 "$tmp/builder.log" | cut -c1-120)"
