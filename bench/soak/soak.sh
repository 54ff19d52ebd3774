#!/bin/sh
# The flight loop's soak: disim fly in real time for DURATION seconds
# (3600 by default) while
#   - one station (disim station --script, id soak-good) flies valid input:
#     small slow movements about the controls it took over;
#   - soak_tx sends every kind of bad traffic at stated rates (random
#     bytes on every channel disim receives, cut messages, NaN, inf and
#     huge values, the genuine station's messages replayed and its id far
#     ahead, take-overs from stations not on the list, a 10 kHz flood of
#     2 s every minute, and sim_control_t hammered: good and bad loads,
#     resets, pause and resume, the instructor's commands, bursts of 20;
#     bench/soak/soak_tx.c has the list);
#   - disim ios, the instructor's console, sends a script of commands
#     every minute (reset hover, wod, sea, turb, snap, restore, freeze and
#     resume) and waits for each answer;
#   - the cores' steal time (/proc/stat: a virtual machine's vCPU runnable
#     but not run by the host) is sampled every second: the loop's
#     overruns beside it;
#   - disim airwaked serves a scratch database (the CG-47's coarse fields
#     copied from --db-from, or none) and is killed with SIGKILL and started
#     again every 2 to 5 minutes (a tenth to a quarter of a short run);
#     six quick and six coarse fields of directions it lacks are queued at
#     the start, so that it is killed mid-build and finishes some.
# The loop flies scenarios/cg47_uh60a_flown.ini (the coarse grid) at 15 kt
# from ahead, sea state 3, with --stations soak-good,soak-trunc,soak-nan,
# soak-huge,soak-flood (the genuine station first) and --wait-after-crash
# (a crash waits for the next reset), logging every message to run.lcm.
# At the end soak_check reads the log back whole and checks the loop's
# counts against what arrived per class, and the database's consistency
# (bench/soak/soak_check.c); summary.json and summary.md in OUT_DIR, and
# the figures printed. Everything runs in a private network namespace
# (unshare -n: LCM's multicast on the namespace's loopback; root or user
# namespaces needed). A terminal gets one progress line; otherwise quiet.
# Exit 0 when the loop ran to its end (exit 0) and every check held; a
# loop still running at 1.5 times DURATION and 5 minutes more is stopped
# with SIGTERM and the run fails.
# usage: bench/soak/soak.sh [DURATION_S] [OUT_DIR] [--build DIR] [--db-from DB]
#        from the source root (OUT_DIR: soak-out; DIR: build, with
#        -DDISIM_BENCH=ON for soak_tx and soak_check)
set -u
dur=3600 out=soak-out build=build dbfrom=
n=0
while [ $# -gt 0 ]; do
    case $1 in
    --build) build=$2; shift 2 ;;
    --db-from) dbfrom=$2; shift 2 ;;
    -*) echo "usage: bench/soak/soak.sh [DURATION_S] [OUT_DIR] [--build DIR] [--db-from DB]" >&2; exit 2 ;;
    *) [ $n -eq 0 ] && dur=$1 || out=$1; n=$((n + 1)); shift ;;
    esac
done
case $dur in '' | *[!0-9]*) echo "soak: DURATION_S: expected whole seconds, got '$dur'" >&2; exit 2 ;; esac
disim=$build/app/disim tx=$build/bench/soak/soak_tx chk=$build/bench/soak/soak_check
for f in "$disim" "$tx" "$chk"; do
    [ -x "$f" ] || { echo "soak: $f: not built (cmake -DDISIM_BENCH=ON; targets disim soak_tx soak_check)" >&2; exit 1; }
done

if [ -z "${SOAK_IN_NS:-}" ]; then # again, inside a private network namespace
    unshare -n true 2> /dev/null || { echo "soak: 'unshare -n' is not permitted here (root or user namespaces)" >&2; exit 1; }
    command -v ip > /dev/null 2>&1 || { echo "soak: the 'ip' command (iproute2) is missing" >&2; exit 1; }
    exec unshare -n env SOAK_IN_NS=1 sh "$0" "$dur" "$out" --build "$build" ${dbfrom:+--db-from "$dbfrom"}
fi
ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo || {
    echo "soak: the namespace's loopback could not be set up for multicast" >&2
    exit 1
}

mkdir -p "$out" || exit 1
[ -z "$(ls -A "$out")" ] || { echo "soak: $out: not empty (a previous run?)" >&2; exit 1; }
out=$(cd "$out" && pwd)
scen=scenarios/cg47_uh60a_flown.ini
tty=0
[ -t 1 ] && tty=1
say() { [ $tty -eq 1 ] && printf '\r\033[K'; echo "soak: $*"; }

# ---- the scratch database: the CG-47's coarse ship-only fields, copied
mkdir -p "$out/db/fields" "$out/bad"
if [ -n "$dbfrom" ]; then
    for f in "$dbfrom"/fields/CG-47_shiponly_*_coarse_*.sum; do
        [ -f "$f" ] || continue
        h=${f%.sum}.h5
        [ -f "$h" ] && cp "$h" "$out/db/fields/" && cp "$f" "$out/db/fields/"
    done
fi
nfields=$(ls "$out/db/fields" | grep -c '\.h5$')
# work for the builder from the start: quick fields of six directions the
# database lacks (15 m/s, the ship-only fields' reference speed), which it
# can finish between two kills, then coarse ones, which it cannot
for g in quick coarse; do
    for d in 45 -45 15 -15 75 -75; do
        "$disim" airwake "$scen" --wod-speed-kt 29.16 --wod-dir-deg $d --rotor off --grid $g --queue "$out/db" \
            > /dev/null 2>&1 || { echo "soak: disim airwake --queue failed" >&2; exit 1; }
    done
done
# ---- what the bad loads name: a FIFO, a file of garbage (missing.ini is not made)
mkfifo "$out/bad/fifo"
head -c 200000 /dev/urandom > "$out/bad/garbage.ini"
# ---- the genuine station's script: slow movements of 1 to 2 % about the
# controls taken over, a row a second for the whole run
awk -v d="$dur" 'BEGIN { print "time_s,collective,long,lat,pedal"
    for (t = 0; t <= d + 600; t++)
        printf "%d,%.2f,%.2f,%.2f,%.2f\n", t, 50 + sin(t / 23), 50 + 1.5 * sin(t / 11), 50 + 1.5 * sin(t / 13 + 1), 50 + sin(t / 17) }' \
    > "$out/good.csv"
cat > "$out/ios.txt" << 'EOF'
reset hover
wod 15 -30
sea 4
turb off
snap ios
freeze
resume
turb on
restore ios
wod 15 0
EOF

pids= bpid=
builder() {
    nice -n 19 "$disim" airwaked "$out/db" --jobs 1 >> "$out/builder.log" 2>&1 &
    bpid=$!
}
cleanup() {
    for p in $pids $bpid; do kill "$p" 2> /dev/null; done
}
trap cleanup EXIT
trap 'exit 130' INT TERM

builder
restarts=0
"$disim" station --script "$out/good.csv" --id soak-good --wait-s 60 > "$out/station.out" 2> "$out/station.err" &
spid=$!
"$tx" --duration $((dur + 900)) --out "$out/sent.json" --good soak-good --scenario "$scen" --bad-dir "$out/bad" \
    > "$out/tx.out" 2> "$out/tx.err" &
txpid=$!
pids="$spid $txpid"
t0=$(date +%s)
steal() { awk '/^cpu /{ print $9; exit }' /proc/stat; }
st0=$(steal) stp=$st0 steal_s=0
"$disim" fly "$scen" --realtime --duration "$dur" --wod-speed-kt 15 --wod-dir-deg 0 --sea-state 3 --db "$out/db" \
    --stations soak-good,soak-trunc,soak-nan,soak-huge,soak-flood --wait-after-crash --log "$out/run.lcm" \
    > "$out/fly.out" 2> "$out/fly.err" &
fpid=$!
pids="$pids $fpid"

# the builder killed every 2 to 5 minutes (a tenth to a quarter of a short run)
kmin=120 kspan=180
[ "$dur" -lt 1200 ] && kmin=$((dur / 10 + 1)) kspan=$((dur * 3 / 20 + 1))
rnd() { od -An -N2 -tu2 /dev/urandom | tr -d ' '; }
next_kill=$((t0 + kmin + $(rnd) % kspan))
next_ios=$((t0 + 30))
ios_runs=0 ios_ok=0 ios_pid=
# a loop still running at 1.5 times its duration and 5 minutes more is
# stopped with SIGTERM (it is stuck: paused or stopped for good) and fails
limit=$((dur * 3 / 2 + 300)) overtime=0
rss0= fd0= rss1= fd1= # the loop's resident memory (kB) and open files, 10 s in and at the last look
while kill -0 "$fpid" 2> /dev/null; do
    now=$(date +%s)
    if [ $((now - t0)) -ge "$limit" ] && [ $overtime -eq 0 ]; then
        overtime=1
        kill -TERM "$fpid"
    fi
    if [ "$now" -ge "$next_kill" ]; then
        kill -KILL "$bpid" 2> /dev/null
        wait "$bpid" 2> /dev/null
        restarts=$((restarts + 1))
        echo "soak: builder killed (SIGKILL) at $((now - t0)) s, restart $restarts" >> "$out/builder.log"
        builder
        next_kill=$((now + kmin + $(rnd) % kspan))
    fi
    if [ -n "$ios_pid" ] && ! kill -0 "$ios_pid" 2> /dev/null; then
        wait "$ios_pid" && ios_ok=$((ios_ok + 1))
        ios_pid=
    fi
    if [ "$now" -ge "$next_ios" ] && [ -z "$ios_pid" ] && [ $((now - t0)) -lt "$dur" ]; then
        echo "--- ios run $((ios_runs + 1)) at $((now - t0)) s" >> "$out/ios.log"
        "$disim" ios --timeout-s 10 --script "$out/ios.txt" >> "$out/ios.log" 2>&1 &
        ios_pid=$!
        ios_runs=$((ios_runs + 1))
        next_ios=$((now + 60))
    fi
    r=$(awk '/^VmRSS:/ { print $2 }' /proc/"$fpid"/status 2> /dev/null)
    d=$(ls /proc/"$fpid"/fd 2> /dev/null | wc -l)
    if [ -n "$r" ]; then
        [ -z "$rss0" ] && [ $((now - t0)) -ge 10 ] && rss0=$r fd0=$d
        rss1=$r fd1=$d
    fi
    st=$(steal)
    [ "$st" -gt "$stp" ] && steal_s=$((steal_s + 1))
    stp=$st
    if [ $tty -eq 1 ]; then
        sz=$(du -m "$out"/run.lcm.tmp* 2> /dev/null | awk '{ s += $1 } END { print s + 0 }')
        printf '\rsoak: %d of %d s, builder restarts %d, instructor runs %d (%d all accepted), log %d MB  ' \
            $((now - t0)) "$dur" "$restarts" "$ios_runs" "$ios_ok" "$sz"
    fi
    sleep 1
done
wait "$fpid"
frc=$?
t1=$(date +%s)
steal_ms=$(( ($(steal) - st0) * 1000 / $(getconf CLK_TCK) ))
[ -n "$ios_pid" ] && { wait "$ios_pid" && ios_ok=$((ios_ok + 1)); }
kill -TERM "$txpid" "$spid" 2> /dev/null
wait "$txpid" "$spid"
kill -TERM "$bpid" 2> /dev/null # the last builder stopped as a user would stop it
wait "$bpid"
brc=$?
pids= bpid=
say "the loop exited $frc after $((t1 - t0)) s of wall time; checking the log and the database"
summ=$(grep -a "s flown in" "$out/fly.err" | tail -1 | sed 's/^.*fly: //')
wake=$(grep -a "wake-up after the deadline" "$out/fly.err" | tail -1 | sed 's/^fly: //')
lcms=$(grep -a "^fly: LCM" "$out/fly.err" | tail -1 | sed 's/^fly: //' | cut -c1-1200 | tr -d '"\\')
left=$(ls "$out" | grep -c '\.tmp')
ios_acc=$(grep -c '^ok:' "$out/ios.log" 2> /dev/null) ios_ref=$(grep -c '^refused:' "$out/ios.log" 2> /dev/null)
ios_other=$(grep -v '^ok:\|^refused:\|^---' "$out/ios.log" 2> /dev/null | grep -c .)
ios_acc=${ios_acc:-0} ios_ref=${ios_ref:-0}
"$chk" --log "$out/run.lcm" --sent "$out/sent.json" --good soak-good --db "$out/db" --json "$out/summary.json" \
    --md "$out/summary.md" --extra "duration_s=$dur" --extra "wall_s=$((t1 - t0))" --extra "fly_exit=$frc" \
    --extra "builder_restarts=$restarts" --extra "builder_last_exit=$brc" --extra "db_fields_at_start=$nfields" \
    --extra "ios_runs=$ios_runs" --extra "ios_runs_all_accepted=$ios_ok" --extra "ios_commands_ok=$ios_acc" \
    --extra "ios_commands_refused=$ios_ref" --extra "ios_other_lines=$ios_other" --extra "steal_ms=$steal_ms" \
    --extra "seconds_with_steal=$steal_s" --timeline "$out/timeline.csv" --extra "fly_summary=$summ" \
    --extra "fly_lcm=$lcms" --extra "temporaries_beside_log=$left" --extra "stopped_overtime=$overtime" \
    --extra "fly_wakeup=$wake" --extra "fly_rss_kB=${rss0:-?} at 10 s, ${rss1:-?} at the end" \
    --extra "fly_open_files=${fd0:-?} at 10 s, ${fd1:-?} at the end"
crc=$?
{
    echo
    [ $overtime -eq 1 ] && echo "FAILED: the loop had not ended after $limit s of wall time: stopped with SIGTERM."
    echo "The run: $dur s of run time asked ($((t1 - t0)) s of wall time), disim fly exit $frc; builder killed and restarted $restarts times (last exit $brc on SIGTERM); $ios_runs instructor scripts ($ios_acc commands accepted, $ios_ref refused, $ios_other other lines: not answered, errors), $ios_ok with every command accepted; $left temporary files beside the log; the host stole $steal_ms ms of CPU, in $steal_s of the run's seconds; the loop's resident memory ${rss0:-?} kB 10 s in, ${rss1:-?} kB at the end, its open files ${fd0:-?} and ${fd1:-?}."
    echo
    echo "disim fly: $summ; $wake"
    echo
    echo "$lcms"
    echo
    echo "Station soak-good: $(tail -1 "$out/station.out" | cut -c1-300)"
} >> "$out/summary.md"
cat "$out/summary.md"
[ "$frc" -eq 0 ] && [ "$crc" -eq 0 ] && [ "$left" -eq 0 ] && [ $overtime -eq 0 ]
