#!/usr/bin/env bash
# Times shlight beside its peers on the same generated 2048x1024 float RGB
# equirect map and prints the ratios.
#
#   benches/peers.sh [LMAX...]        (default: 2 8 32 128 512)
#
# Installs what it needs into target/peers/: ducc0 from PyPI in a virtual
# environment, Filament's cmgen from the Debian package libfilament-tools
# when apt can install it (skipped with a note otherwise). Both cores are
# used by every tool (ducc0 nthreads=2, rayon's default).
#
# What is timed:
#   shlight   projection alone, in-process (cargo bench --bench projection is
#             the divan benchmark; here the `shlight project` binary end to end
#             on the same map as .hdr, minus nothing: decode + project + write)
#   ducc0     ducc0.sht.adjoint_synthesis_2d on the in-memory array (geometry
#             F1: rows at theta = (j + 1/2) pi / H, the equirect texel centres)
#   cmgen     cmgen --sh=3 end to end from the .hdr (lmax 2 only)
set -euo pipefail
cd "$(dirname "$0")/.."
LMAXES=("${@:-2 8 32 128 512}")
[ $# -eq 0 ] && LMAXES=(2 8 32 128 512)
DIR=target/peers
mkdir -p "$DIR"

echo "== building shlight (release)"
cargo build --release --quiet
SHLIGHT=target/release/shlight

if [ ! -x "$DIR/venv/bin/python" ]; then
    echo "== installing ducc0 and numpy into $DIR/venv"
    python3 -m venv "$DIR/venv"
    "$DIR/venv/bin/pip" install --quiet ducc0 numpy
fi
PY="$DIR/venv/bin/python"

CMGEN=$(command -v cmgen || true)
if [ -z "$CMGEN" ] && command -v apt-get >/dev/null; then
    echo "== trying apt-get install libfilament-tools (for cmgen)"
    (apt-get install -y -qq libfilament-tools >/dev/null 2>&1 || sudo -n apt-get install -y -qq libfilament-tools >/dev/null 2>&1) || true
    CMGEN=$(command -v cmgen || true)
fi
[ -z "$CMGEN" ] && echo "note: cmgen not available (Debian package libfilament-tools); its row is skipped"

echo "== generating the 2048x1024 map"
"$PY" - "$DIR" <<'PY'
import sys, numpy as np
d = sys.argv[1]
W, H = 2048, 1024
y, x = np.mgrid[0:H, 0:W]
u, v = (x + .5) / W, (y + .5) / H
noise = ((np.arange(W * H).reshape(H, W) * 7919) % 101) * 1e-3
sun = ((abs(u - .3) < .01) & (abs(v - .2) < .02)) * 5e3
img = np.stack([1 - v + sun + noise, .8 - .5 * v + sun, .6 + .3 * u + sun], -1).astype(np.float32)
np.save(f"{d}/map.npy", img)
# Radiance RGBE writer (flat, not run-length encoded).
m = img.max(-1)
e = np.where(m > 1e-32, np.ceil(np.log2(np.maximum(m, 1e-32)) + 1e-9), 0).astype(np.int32)
scale = np.where(m > 1e-32, 256.0 / np.exp2(e), 0)
rgbe = np.zeros((H, W, 4), np.uint8)
rgbe[..., :3] = np.clip(img * scale[..., None], 0, 255).astype(np.uint8)
rgbe[..., 3] = np.where(m > 1e-32, e + 128, 0)
with open(f"{d}/map.hdr", "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (H, W))
    f.write(rgbe.tobytes())
PY

median_ms() { # command... -> median wall time of 7 runs in ms
    "$PY" - "$@" <<'PY'
import subprocess, sys, time, statistics
ts = []
for _ in range(7):
    t = time.perf_counter(); subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL); ts.append(time.perf_counter() - t)
print(f"{statistics.median(ts) * 1e3:.1f}")
PY
}

echo
printf "%-6s %14s %14s %14s %10s\n" lmax "shlight (ms)" "ducc0 (ms)" "cmgen (ms)" "ducc0/shl"
for L in "${LMAXES[@]}"; do
    S=$(median_ms "$SHLIGHT" project "$DIR/map.hdr" --up z --lmax "$L" -o "$DIR/out.json" --quiet)
    D=$("$PY" - "$DIR" "$L" <<'PY'
import sys, time, statistics, numpy as np, ducc0
d, L = sys.argv[1], int(sys.argv[2])
img = np.load(f"{d}/map.npy").astype(np.float64)
ts = []
for _ in range(7):
    t = time.perf_counter()
    for c in range(3):
        ducc0.sht.experimental.adjoint_synthesis_2d(map=img[None, :, :, c], spin=0, lmax=L, geometry="F1", nthreads=2)
    ts.append(time.perf_counter() - t)
print(f"{statistics.median(ts) * 1e3:.1f}")
PY
)
    C="-"
    if [ -n "$CMGEN" ] && [ "$L" = 2 ]; then
        C=$(median_ms "$CMGEN" --quiet --sh=3 --sh-output="$DIR/cmgen_sh.txt" "$DIR/map.hdr")
    fi
    R=$("$PY" -c "print(f'{$D / $S:.2f}')")
    printf "%-6s %14s %14s %14s %10s\n" "$L" "$S" "$D" "$C" "$R"
done
echo
echo "shlight's projection alone (no decode): cargo bench -p shlight-core --bench projection"
