#!/usr/bin/env bash
# Times shlight beside its peers on the same generated 2048x1024 float RGB
# equirect map and prints the ratios.
#
#   benches/peers.sh [LMAX...]        (default: 2 8 32 128 512)
#
# Environment: PEERS_DIR (default target/peers) holds the virtual
# environment and the maps; SHLIGHT names the binary to time (default: built
# here in release, under CARGO_TARGET_DIR or target/).
#
# Installs what it needs into $PEERS_DIR: ducc0, numpy and OpenEXR (the
# Academy Software Foundation's Python bindings) from PyPI in a virtual
# environment, Filament's cmgen from the Debian package libfilament-tools
# when apt can install it (skipped with a note otherwise). Every tool uses
# every core (ducc0 nthreads = the core count, rayon's default).
#
# Two tables:
#
# 1. End to end on a 2048x1024 float OpenEXR (ZIP, the OpenEXR default),
#    made from envmaps/park.exr by bilinear upsampling: `shlight project
#    MAP.exr --lmax L --up y|z -o out.json` (process start to exit: read,
#    statistics, projection, quarter turn for y-up, writing the file)
#    against the peer pair, OpenEXR's reader plus ducc0's
#    adjoint_synthesis_2d of the three channels in one Python process
#    timed two ways: inside the process ("pair in", without the
#    interpreter's start and imports, its memory warm after the first of
#    the 7 runs), and as a whole process ("pair proc", start to exit, the
#    way shlight is timed). The pair writes nothing. Medians of 7 runs;
#    ratios = shlight / pair (below 1: shlight is faster).
#
# 2. Against each peer on the generated map below, z-up; what is timed:
#   shlight   projection alone, in-process (cargo bench --bench projection is
#             the divan benchmark; here the `shlight project` binary end to end
#             on the same map as .hdr, minus nothing: decode + project + write)
#   ducc0     ducc0.sht.adjoint_synthesis_2d on the in-memory array (geometry
#             F1: rows at theta = (j + 1/2) pi / H, the equirect texel centres)
#   cmgen     cmgen --sh=3 end to end from the .hdr (lmax 2 only)
set -euo pipefail
cd "$(dirname "$0")/.."
LMAXES=("$@")
[ $# -eq 0 ] && LMAXES=(2 8 32 128 512)
DIR=${PEERS_DIR:-target/peers}
mkdir -p "$DIR"

if [ -z "${SHLIGHT:-}" ]; then
    echo "== building shlight (release)"
    cargo build --release --quiet -p shlight
    SHLIGHT=${CARGO_TARGET_DIR:-target}/release/shlight
fi

if [ ! -x "$DIR/venv/bin/python" ]; then
    python3 -m venv "$DIR/venv"
fi
if ! "$DIR/venv/bin/python" -c "import ducc0, numpy, OpenEXR" 2>/dev/null; then
    echo "== installing ducc0, numpy and OpenEXR into $DIR/venv"
    "$DIR/venv/bin/pip" install --quiet ducc0 numpy OpenEXR
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

echo "== end to end: 2048x1024 float OpenEXR (ZIP) from envmaps/park.exr"
"$PY" - "$DIR/map.exr" envmaps/park.exr <<'PY'
import sys, numpy as np, OpenEXR
out, src = sys.argv[1], sys.argv[2]
with OpenEXR.File(src) as f:
    ch = f.channels()
    # Separate R, G, B channels, or one interleaved "RGB" entry.
    img = (np.stack([ch[c].pixels for c in "RGB"], -1) if "R" in ch else ch["RGB"].pixels).astype(np.float32)
H, W = 1024, 2048
h, w = img.shape[:2]
ys = (np.arange(H) + .5) * h / H - .5
xs = (np.arange(W) + .5) * w / W - .5
y0 = np.clip(np.floor(ys).astype(int), 0, h - 1); y1 = np.clip(y0 + 1, 0, h - 1)
fy = np.clip(ys - np.floor(ys), 0, 1)[:, None, None]
x0 = np.floor(xs).astype(int) % w; x1 = (x0 + 1) % w
fx = (xs - np.floor(xs))[None, :, None]
top = img[y0][:, x0] * (1 - fx) + img[y0][:, x1] * fx
bottom = img[y1][:, x0] * (1 - fx) + img[y1][:, x1] * fx
up = (top * (1 - fy) + bottom * fy).astype(np.float32)
header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
channels = {c: OpenEXR.Channel(np.ascontiguousarray(up[..., i])) for i, c in enumerate("RGB")}
with OpenEXR.File(header, channels) as f:
    f.write(out)
PY

# The peer pair: OpenEXR's reader and ducc0 on the three channels. With a
# third argument RUNS it repeats that many times in this one process and
# prints the median in ms; without, it runs once and prints nothing (timed
# from outside, as a whole process).
cat >"$DIR/pair.py" <<'PY'
import os, sys, time, statistics, numpy as np, OpenEXR, ducc0
path, L = sys.argv[1], int(sys.argv[2])
runs = int(sys.argv[3]) if len(sys.argv) > 3 else 1
ts = []
for _ in range(runs):
    t = time.perf_counter()
    with OpenEXR.File(path) as f:
        ch = f.channels()
        planes = [ch[c].pixels for c in "RGB"] if "R" in ch else [ch["RGB"].pixels[..., c] for c in range(3)]
    for p in planes:
        ducc0.sht.experimental.adjoint_synthesis_2d(
            map=p[None].astype(np.float64), spin=0, lmax=L, geometry="F1", nthreads=os.cpu_count())
    ts.append(time.perf_counter() - t)
if len(sys.argv) > 3:
    print(f"{statistics.median(ts) * 1e3:.1f}")
PY

pair_ms() { # map lmax -> median ms of OpenEXR read + ducc0 over 7 runs in one process
    "$PY" "$DIR/pair.py" "$1" "$2" 7
}

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
echo "end to end (ms, medians of 7; ratios = shlight / pair in, shlight / pair proc)"
printf "%-6s %9s %10s %10s %6s %6s %10s %6s %6s\n" lmax "pair in" "pair proc" "shlight y" "y/in" "y/proc" \
    "shlight z" "z/in" "z/proc"
ratio() { "$PY" -c "print(f'{$1 / $2:.2f}')"; }
for L in "${LMAXES[@]}"; do
    P=$(pair_ms "$DIR/map.exr" "$L")
    Q=$(median_ms "$PY" "$DIR/pair.py" "$DIR/map.exr" "$L")
    Y=$(median_ms "$SHLIGHT" project "$DIR/map.exr" --up y --lmax "$L" -o "$DIR/out.json" --quiet)
    Z=$(median_ms "$SHLIGHT" project "$DIR/map.exr" --up z --lmax "$L" -o "$DIR/out.json" --quiet)
    printf "%-6s %9s %10s %10s %6s %6s %10s %6s %6s\n" "$L" "$P" "$Q" "$Y" "$(ratio "$Y" "$P")" \
        "$(ratio "$Y" "$Q")" "$Z" "$(ratio "$Z" "$P")" "$(ratio "$Z" "$Q")"
done

echo
echo "projection alone against ducc0 (ms; the .hdr map; ratio = ducc0 / shlight)"
printf "%-6s %14s %14s %14s %10s\n" lmax "shlight (ms)" "ducc0 (ms)" "cmgen (ms)" "ducc0/shl"
for L in "${LMAXES[@]}"; do
    S=$(median_ms "$SHLIGHT" project "$DIR/map.hdr" --up z --lmax "$L" -o "$DIR/out.json" --quiet)
    D=$("$PY" - "$DIR" "$L" <<'PY'
import os, sys, time, statistics, numpy as np, ducc0
d, L = sys.argv[1], int(sys.argv[2])
img = np.load(f"{d}/map.npy").astype(np.float64)
ts = []
for _ in range(7):
    t = time.perf_counter()
    for c in range(3):
        ducc0.sht.experimental.adjoint_synthesis_2d(map=img[None, :, :, c], spin=0, lmax=L, geometry="F1", nthreads=os.cpu_count())
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
