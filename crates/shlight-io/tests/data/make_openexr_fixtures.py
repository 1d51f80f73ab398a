"""Writes the OpenEXR fixtures in this directory with the OpenEXR C++ library
and prints the fingerprint of each as OpenEXR decodes it (the table
OPENEXR_WRITTEN in ../openexr.rs).

    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install openexr==3.5.3 numpy
    /tmp/venv/bin/python crates/shlight-io/tests/data/make_openexr_fixtures.py

Run from the workspace root after envmaps/fetch.sh. The content is a 48x24
crop of envmaps/studio.exr around its brightest pixel.
"""

import os

import numpy as np
import OpenEXR as C

OUT = os.path.dirname(os.path.abspath(__file__))


def fingerprint(rgb):
    """FNV-1a (64 bit) over the f32 bit patterns, R, G, B row-major."""
    h = 0xCBF29CE484222325
    for w in rgb.astype(np.float32).reshape(-1).view(np.uint32).tolist():
        h = ((h ^ w) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def write(name, header, channels):
    path = os.path.join(OUT, name)
    # OpenEXR.File turns the dict's arrays into Channel objects: give it a copy.
    C.File(header, dict(channels)).write(path)
    try:
        with C.File(path, separate_channels=True) as f:
            c = f.channels()
            rgb = np.stack([c[k].pixels.astype(np.float32) for k in "RGB"], -1)
        print(f'("{name}", 0x{fingerprint(rgb):016x}),')
    except Exception as e:  # compressions this build cannot decode
        print(f"{name}: written, not decoded here ({e})")


with C.File("envmaps/studio.exr", separate_channels=True) as f:
    full = {k: v.pixels for k, v in f.channels().items()}
r = full["R"].astype(np.float32)
y, x = np.unravel_index(np.argmax(r), r.shape)
y0, x0 = max(0, min(256 - 24, y - 12)), max(0, min(512 - 48, x - 24))
crop = {k: np.ascontiguousarray(v[y0 : y0 + 24, x0 : x0 + 48]) for k, v in full.items()}
scanlines = lambda compression: {"compression": compression, "type": C.scanlineimage}

for compression, name in [
    (C.RLE_COMPRESSION, "rle"),
    (C.ZIPS_COMPRESSION, "zips"),
    (C.ZIP_COMPRESSION, "zip"),
    (C.PIZ_COMPRESSION, "piz"),
    (C.PXR24_COMPRESSION, "pxr24"),
    (C.B44_COMPRESSION, "b44"),
    (C.B44A_COMPRESSION, "b44a"),
    (C.DWAA_COMPRESSION, "dwaa"),
    (C.DWAB_COMPRESSION, "dwab"),
]:
    write(f"openexr-{name}-half.exr", scanlines(compression), crop)
for compression, name in [
    (C.PIZ_COMPRESSION, "piz"),
    (C.PXR24_COMPRESSION, "pxr24"),
    (C.DWAA_COMPRESSION, "dwaa"),
]:
    floats = {k: v.astype(np.float32) for k, v in crop.items()}
    write(f"openexr-{name}-float.exr", scanlines(compression), floats)
tiles = C.TileDescription()
tiles.xSize, tiles.ySize, tiles.mode = 16, 16, C.ONE_LEVEL
write(
    "openexr-tiled-zip-half.exr",
    {"compression": C.ZIP_COMPRESSION, "type": C.tiledimage, "tiles": tiles},
    crop,
)
# Compressions newer than the exr crate's decoders (OpenEXR 3.4+).
write("openexr-htj2k256-half.exr", scanlines(C.HTJ2K256_COMPRESSION), crop)
write("openexr-zstd-half.exr", scanlines(C.ZSTD_COMPRESSION), crop)
