#!/usr/bin/env bash
# PRT rays per second, shlight beside Embree, on the same rays: the
# benchmark torus (69,696 triangles), every 8th direction of the
# 1024-direction grid, each cast from the vertices facing it in the order
# baking casts them (about 2.27 M rays, ~11% of them hit).
#
#   benches/prt_peers.sh
#
# Installs Embree 4 from PyPI (the embreex wheel, as used by trimesh) into
# target/peers/venv. What is timed (best of 3 each, the rays already in
# memory):
#   shlight   crates/shlight-rays/examples/prt_rays.rs: packets of eight
#             parallel rays (AVX2), occlusion and closest hits, on one
#             thread and on all cores
#   embree    rtcOccluded1 / rtcIntersect1 per ray (embreex's scene.run),
#             one thread: Embree's single-ray path
set -euo pipefail
cd "$(dirname "$0")/.."
DIR=target/peers
mkdir -p "$DIR"

if [ ! -x "$DIR/venv/bin/python" ]; then
    python3 -m venv "$DIR/venv"
fi
if ! "$DIR/venv/bin/python" -c "import embreex, numpy" 2>/dev/null; then
    echo "== installing embreex (Embree 4) and numpy into $DIR/venv"
    "$DIR/venv/bin/pip" install --quiet embreex numpy
fi

echo "== shlight (writes $DIR/prt_rays.bin)"
cargo run --release --quiet -p shlight-rays --example prt_rays -- "$DIR/prt_rays.bin"

echo "== embree"
"$DIR/venv/bin/python" - "$DIR/prt_rays.bin" <<'PY'
import sys, time
import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

b = open(sys.argv[1], "rb").read()
nv, nt, nr = (int(x) for x in np.frombuffer(b[:12], dtype=np.uint32))
off = 12
pos = np.frombuffer(b[off:off + nv * 12], dtype=np.float32).reshape(-1, 3)
off += nv * 12
tri = np.frombuffer(b[off:off + nt * 12], dtype=np.uint32).reshape(-1, 3)
off += nt * 12
rays = np.frombuffer(b[off:off + nr * 24], dtype=np.float32).reshape(-1, 6)
scene = rtcs.EmbreeScene()
TriangleMesh(scene, pos.copy(), tri.astype(np.int32))
o = np.ascontiguousarray(rays[:, :3])
d = np.ascontiguousarray(rays[:, 3:])
for name, query in (("occluded", "OCCLUDED"), ("closest", "INTERSECT")):
    best, out = float("inf"), None
    for _ in range(3):
        start = time.perf_counter()
        out = scene.run(o, d, query=query)
        best = min(best, time.perf_counter() - start)
    hit = int((np.asarray(out) != -1).sum()) if query == "INTERSECT" else int(nr + np.asarray(out).sum())
    print(f"embree {name}, 1 thread: {nr} rays in {best:.3f} s -> {nr / best / 1e6:.2f} M rays/s ({hit} hit)")
PY
