#!/usr/bin/env bash
# Peak memory and time of `shlight project` on large maps, before and after
# reading by rows, as medians of paired runs (before and after alternate,
# so both see the same load on a shared machine).
#
#   SHLIGHT_BEFORE=path/to/old/shlight benches/stream.sh [RUNS]
#
# The maps are written once into $SHLIGHT_BENCH_DIR (default
# target/bench-maps) by the ignored test `stream::write_benchmark_maps`:
# park.exr resized to 2048x1024 and 8192x4096 with a texel ripple (float
# ZIP OpenEXR, compressing as a photographed map does), and patchy maps at
# 8192x4096 and 16384x8192. Needs GNU time (/usr/bin/time).
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-5}
BEFORE=${SHLIGHT_BEFORE:?set SHLIGHT_BEFORE to the shlight binary to compare with}
AFTER=${SHLIGHT_AFTER:-target/release/shlight}
export SHLIGHT_BENCH_DIR=${SHLIGHT_BENCH_DIR:-target/bench-maps}
if [ ! -f "$SHLIGHT_BENCH_DIR/patches-16384.exr" ]; then
    cargo test --release --test tests stream::write_benchmark_maps -- --ignored
fi
[ -n "${SHLIGHT_AFTER:-}" ] || cargo build --release --quiet
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

# One run: "seconds max-RSS-KB".
run() {
    /usr/bin/time -f "%e %M" -o "$OUT/t" "$@" >/dev/null 2>&1
    cat "$OUT/t"
}

median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }

printf '| map | lmax | before s | before MB | after s | after MB | time after/before |\n'
printf '|---|---|---|---|---|---|---|\n'
for map in park-2048 park-8192 patches-8192 patches-16384; do
    for lmax in 8 64; do
        : >"$OUT/b"; : >"$OUT/a"
        for _ in $(seq "$RUNS"); do
            run "$BEFORE" project "$SHLIGHT_BENCH_DIR/$map.exr" --lmax $lmax -o "$OUT/b.json" --quiet >>"$OUT/b"
            run "$AFTER" project "$SHLIGHT_BENCH_DIR/$map.exr" --lmax $lmax -o "$OUT/a.json" --quiet >>"$OUT/a"
        done
        cmp -s "$OUT/a.json" "$OUT/b.json" || { echo "$map lmax $lmax: the files differ" >&2; exit 1; }
        bs=$(cut -d' ' -f1 "$OUT/b" | median); bm=$(cut -d' ' -f2 "$OUT/b" | median)
        as=$(cut -d' ' -f1 "$OUT/a" | median); am=$(cut -d' ' -f2 "$OUT/a" | median)
        awk -v m="$map" -v l=$lmax -v bs="$bs" -v bm="$bm" -v as="$as" -v am="$am" 'BEGIN {
            printf "| %s | %d | %.2f | %.0f | %.2f | %.0f | %.2f |\n", m, l, bs, bm / 1024, as, am / 1024, as / bs }'
    done
done
