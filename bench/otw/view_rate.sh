#!/bin/sh
# The station's out-the-window view beside the flight loop: disim fly
# --realtime --stations pilot1 (200 Hz, states at 50 Hz on LCM) and disim
# station --view CAMERA --id pilot1 at WxH under Xvfb (a screen of that
# size, 24 bits), both inside one private network namespace with multicast
# on loopback (docs/conventions.md). The station starts first and takes its
# scene from the loop's run_info_t; it flies a script holding the hover's
# trim (the loop with the SAS on, no turbulence). Prints the station's report (frames/s shown, latency
# from a state's arrival to SDL_RenderPresent p50 / p99 / max, drawing time
# p50 / p99, the SDL renderer), the loop's summary, and where a frame's
# time goes from the --view-stats CSV (draw, and the rest: waiting in the
# mailbox, the texture upload, the present).
# Usage, from the source root, as root (unshare -n):
#   bench/otw/view_rate.sh [DISIM] [SECONDS] [WxH] [CAMERA] [IMAGE_WxH]
# (./build/app/disim, 30, 1280x720, pilot, the station's default image:
# the window's size). CAMERA none: the station
# without --view, the baseline of its late deadlines and the loop's
# overruns. SDL_RENDER_DRIVER (software,
# opengl) and LP_NUM_THREADS are passed through.
set -u
disim=${1:-./build/app/disim} secs=${2:-30} size=${3:-1280x720} cam=${4:-pilot} image=${5:-}
tmp=$(mktemp -d /tmp/disim_view_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
# the hover's trim (disim fly --csv's first row), held by the station
printf '0,55.126,45.486,43.267,31.573\n' > "$tmp/trim.csv"
echo "view_rate: $cam camera, window $size, image ${image:-the same}, beside disim fly --realtime for $secs s on $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
unshare -n sh -c '
ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo || exit 1
disim=$1 secs=$2 size=$3 cam=$4 tmp=$5 FLY_FLAGS=$6 image=$7
xvfb-run -a -s "-screen 0 ${size}x24" sh -c "
view=\"--view $cam --view-size $size \${image:+--view-image \$image} --view-stats $tmp/frames.csv\"
[ $cam = none ] && view=
\"$disim\" station \$view --id pilot1 --script \"$tmp/trim.csv\" --script-absolute \
    --duration $((secs + 6)) > \"$tmp/station.out\" 2> \"$tmp/station.err\" & s=\$!
sleep 2
\"$disim\" fly scenarios/cg47_uh60a.ini --realtime --stations pilot1 --duration $secs --wod-speed-kt 20 --wod-dir-deg -30 ${FLY_FLAGS:---sas on --no-turbulence} > \"$tmp/fly.out\" 2>&1
wait \$s
"
' sh "$disim" "$secs" "$size" "$cam" "$tmp" "${FLY_FLAGS:---sas on --no-turbulence}" "$image"
grep "view:" "$tmp/station.err" || tail -3 "$tmp/station.err"
grep "^end:" "$tmp/station.out" | cut -c1-200
grep -v "^\r" "$tmp/fly.out" | tail -4
# where a frame's time goes, the frames after the first second of the run
# (--view-stats columns: arrival 3, drawing 4-5, upload 6, present 7, shown 8)
pct() { # EXPRESSION: its p50 and p99 over the frames, ms
    awk -F, "NR > 1 && \$2 > 1.0 && \$9 == \$9 + 0 { print ($1) * 1e3 }" "$tmp/frames.csv" | sort -g |
        awk '{ v[NR] = $1 } END { if (NR) printf "p50 %.1f p99 %.1f ms", v[int(NR * 0.5 + 0.5)], v[int(NR * 0.99 + 0.5)] }'
}
[ -e "$tmp/frames.csv" ] || exit 0
n=$(awk -F, 'NR > 1 && $2 > 1.0 && $9 == $9 + 0' "$tmp/frames.csv" | wc -l)
echo "view_rate: $n frames: latency $(pct '$9')"
echo "  waiting for the drawing thread (arrival to drawing) $(pct '$4 - $3')"
echo "  drawing (render_frame: the scene, the strip)        $(pct '$5 - $4')"
echo "  waiting for the window (drawn to upload)            $(pct '$6 - $5')"
echo "  upload (SDL_UpdateTexture, SDL_RenderCopy)          $(pct '$7 - $6')"
echo "  SDL_RenderPresent                                   $(pct '$8 - $7')"
