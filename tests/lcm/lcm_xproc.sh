#!/bin/sh
# Cross-process publish/subscribe over UDP multicast, inside a private network
# namespace so that nothing leaves loopback (docs/conventions.md). Where unshare
# or ip is missing: skipped (exit 77), and a failure with CI set
# (tests/skip.sh).
# Usage: lcm_xproc.sh LCM_XPROC_BINARY
set -u
bin=$1
. "$(dirname "$0")/../skip.sh"
unshare -n true 2>/dev/null || skip lcm_xproc "'unshare -n' is not permitted here (needs root or user namespaces)"
command -v ip >/dev/null 2>&1 || skip lcm_xproc "the 'ip' command (iproute2) is missing"
exec unshare -n sh -c '
set -e
ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
"$1" sub 50 & sub=$!
sleep 0.3
"$1" pub 50
wait $sub
' sh "$bin"
