#!/bin/sh
# LCM stays on the host by default. Two private network namespaces joined by
# a veth pair, with multicast routed over it: "this host" runs disim fly in
# real time, "the other host" counts the helicopter states that reach it.
# With disim's default URL (LCM_DEFAULT_URL unset) the other host gets none
# while a listener on this host gets them; with a ttl=1 URL, the way to
# reach other hosts, it gets them too (the pair does carry multicast). The
# start line names the URL. Where unshare or ip is missing: skipped (exit
# 77), a failure with CI set (tests/skip.sh).
# Usage: lcm_ttl.sh DISIM LCM_XPROC SOURCE_DIR
set -u
. "$(dirname "$0")/../skip.sh"
unshare -n true 2>/dev/null || skip lcm_ttl "'unshare -n' is not permitted here (needs root or user namespaces)"
command -v ip >/dev/null 2>&1 || skip lcm_ttl "the 'ip' command (iproute2) is missing"
unshare -n sh -c 'ip link add t0 type veth peer name t1' 2>/dev/null ||
    skip lcm_ttl "veth pairs cannot be made here"
tmp=$(mktemp -d /tmp/disim_lcm_ttl_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
unset LCM_DEFAULT_URL
# round URL NAME: fly 3 s with URL (empty: the default); counts in NAME.here, NAME.there
round() {
    unshare -n sh -c '
    set -e
    disim=$1 xproc=$2 src=$3 tmp=$4 url=$5 name=$6
    ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo
    ip link add va type veth peer name vb
    unshare -n sh -c "
        touch \"$tmp/$name.ns\"
        while ! ip link show vb > /dev/null 2>&1; do sleep 0.05; done
        ip link set lo up && ip addr add 10.77.0.2/24 dev vb && ip link set vb up
        ip route add 224.0.0.0/4 dev vb
        exec \"$xproc\" count 7" > "$tmp/$name.there" & there=$!
    while [ ! -e "$tmp/$name.ns" ]; do sleep 0.05; done # in its own namespace
    ip link set vb netns $there
    ip addr add 10.77.0.1/24 dev va && ip link set va up && ip link set va multicast on
    ip route del 224.0.0.0/4 dev lo && ip route add 224.0.0.0/4 dev va
    "$xproc" count 7 > "$tmp/$name.here" & here=$!
    sleep 1
    cd "$src"
    if [ -n "$url" ]; then lcm="--lcm $url"; else lcm=; fi
    "$disim" fly scenarios/cg47_uh60a.ini --realtime --duration 3 --wod-speed-kt 20 --wod-dir-deg 0 --no-turbulence $lcm > "$tmp/$name.fly" 2>&1
    wait $here $there
    ' sh "$1" "$2" "$3" "$tmp" "$4" "$5"
}
fail=0
round "$1" "$2" "$3" "" default || { echo "lcm_ttl: the default round failed"; cat "$tmp"/default.* ; exit 1; }
round "$1" "$2" "$3" "udpm://239.255.76.67:7667?ttl=1" ttl1 || { echo "lcm_ttl: the ttl=1 round failed"; cat "$tmp"/ttl1.*; exit 1; }
h0=$(cat "$tmp/default.here") t0=$(cat "$tmp/default.there") h1=$(cat "$tmp/ttl1.here") t1=$(cat "$tmp/ttl1.there")
echo "lcm_ttl: default URL: $h0 states on this host, $t0 on the other; ttl=1: $h1 and $t1"
grep -o "LCM udpm://[^ ]* ([a-z ]*" "$tmp/default.fly" || { echo "lcm_ttl: the start line names no URL:"; head -3 "$tmp/default.fly"; fail=1; }
grep -q "LCM udpm://239.255.76.67:7667?ttl=0 (this host only)" "$tmp/default.fly" || { echo "lcm_ttl: expected the default URL with ttl=0, this host only"; fail=1; }
[ "$h0" -ge 100 ] || { echo "lcm_ttl: expected at least 100 states (50 Hz for 3 s) on this host with the default URL"; fail=1; }
[ "$t0" -eq 0 ] || { echo "lcm_ttl: expected no state on the other host with the default URL"; fail=1; }
[ "$t1" -ge 100 ] || { echo "lcm_ttl: expected at least 100 states on the other host with ttl=1 (the veth pair carries none?)"; fail=1; }
exit $fail
