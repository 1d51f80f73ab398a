#!/usr/bin/env bash
# The scanned room's volume end to end: `shlight volume` from process start
# to exit (reading the 145k-triangle OBJ, subdividing, building the
# hierarchy, the 16x8x16 probes' 4,096 rays each, 2 bounces, writing the
# file), RUNS times, with each run's wall, user and system seconds and
# peak memory, then the medians. Before timing, the scene is written once
# by the volume bench's own generator (the room and two dense scans;
# `cargo run --release -p shlight-volume --example scan_scene`) into
# $SHLIGHT_BENCH_DIR (default target/bench-scan). Needs GNU time.
#
#   benches/scan_room.sh [RUNS]                 # this checkout's build
#   SHLIGHT=path/to/shlight benches/scan_room.sh  # another build
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-5}
DIR=${SHLIGHT_BENCH_DIR:-target/bench-scan}
if [ -z "${SHLIGHT:-}" ]; then
    cargo build --release --quiet
    SHLIGHT=target/release/shlight
fi
if [ ! -f "$DIR/scan_scene.obj" ]; then
    cargo run --release --quiet -p shlight-volume --example scan_scene -- "$DIR"
fi
[ -f "$DIR/park.json" ] || "$SHLIGHT" project envmaps/park.exr -o "$DIR/park.json" 2>/dev/null
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "wall_s user_s sys_s peak_kb"
for _ in $(seq "$RUNS"); do
    /usr/bin/time -f "%e %U %S %M" -o "$OUT/t" "$SHLIGHT" volume "$DIR/scan_scene.obj" \
        --env "$DIR/park.json" --resolution 16x8x16 --samples 4096 --bounces 2 \
        --surface-samples 256 -o "$OUT/scan.shvol" >/dev/null 2>&1
    cat "$OUT/t" | tee -a "$OUT/all"
    rm -f "$OUT/scan.shvol"
done
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
echo "median wall $(cut -d' ' -f1 "$OUT/all" | median) s," \
    "cpu $(awk '{print $2+$3}' "$OUT/all" | median) s," \
    "peak $(cut -d' ' -f4 "$OUT/all" | median) KB; load $(cut -d' ' -f1-3 /proc/loadavg)"
