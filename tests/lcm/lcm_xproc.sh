#!/bin/sh
# Cross-process publish/subscribe over UDP multicast, inside a private network
# namespace so that nothing leaves loopback (CONVENTIONS.md). Exit 77 (ctest:
# skipped) with a message where unshare is not permitted.
# Usage: lcm_xproc.sh LCM_XPROC_BINARY
set -u
bin=$1
if ! unshare -n true 2>/dev/null; then
    echo "lcm_xproc: SKIPPED: 'unshare -n' is not permitted here (needs root or user namespaces)"
    exit 77
fi
if ! command -v ip >/dev/null 2>&1; then
    echo "lcm_xproc: SKIPPED: the 'ip' command (iproute2) is missing"
    exit 77
fi
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
