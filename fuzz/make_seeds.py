"""Writes the seed corpus of every fuzz target under fuzz/corpus/ (small
files: 16x8 images, meshes of a few triangles, 2x2x2 volumes), from the
bundled envmaps/studio.exr, meshes/cornell_box.obj and .mtl, and a
shlight binary.

    python3 fuzz/make_seeds.py path/to/shlight

Run from the workspace root after envmaps/fetch.sh. Needs numpy and the
OpenEXR Python bindings and Pillow (pip install openexr==3.5.3 numpy
pillow). The
files are checked in; rerun only to change them.
"""

import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile

import numpy as np
import OpenEXR as C

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "fuzz", "corpus")
SHLIGHT = os.path.abspath(sys.argv[1])


def out(target, name, data):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


# --- A 16x8 crop of studio.exr around its brightest pixel -------------------
with C.File(os.path.join(ROOT, "envmaps", "studio.exr"), separate_channels=True) as f:
    full = {k: v.pixels for k, v in f.channels().items() if k in "RGB"}
r = full["R"].astype(np.float32)
y, x = np.unravel_index(np.argmax(r), r.shape)
H, W = 8, 16
y0, x0 = max(0, min(r.shape[0] - H, y - H // 2)), max(0, min(r.shape[1] - W, x - W // 2))
crop = {k: np.ascontiguousarray(v[y0 : y0 + H, x0 : x0 + W]).astype(np.float16) for k, v in full.items()}
rgb = np.stack([crop[k].astype(np.float32) for k in "RGB"], -1)


# --- OpenEXR: one file per compression the reader decodes, and layouts ------
def exr(name, header, channels):
    tmp = tempfile.mktemp(suffix=".exr")
    C.File(header, dict(channels)).write(tmp)
    with open(tmp, "rb") as f:
        out("exr", name, f.read())
    os.remove(tmp)


scan = lambda c: {"compression": c, "type": C.scanlineimage}
for c, n in [
    (C.NO_COMPRESSION, "none"),
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
    exr(f"{n}-half.exr", scan(c), crop)
floats = {k: v.astype(np.float32) for k, v in crop.items()}
for c, n in [(C.NO_COMPRESSION, "none"), (C.PIZ_COMPRESSION, "piz"), (C.PXR24_COMPRESSION, "pxr24"), (C.DWAA_COMPRESSION, "dwaa")]:
    exr(f"{n}-float.exr", scan(c), floats)
exr("zip-uint.exr", scan(C.ZIP_COMPRESSION), {k: (v.astype(np.float32) * 100).astype(np.uint32) for k, v in crop.items()})
exr("rle-grey.exr", scan(C.RLE_COMPRESSION), {"Y": crop["G"]})
exr("zip-layers.exr", scan(C.ZIP_COMPRESSION), {**{"diffuse." + k: v for k, v in crop.items()}, "A": crop["R"]})
for mode, n in [(C.ONE_LEVEL, "one"), (C.MIPMAP_LEVELS, "mipmap")]:
    tiles = C.TileDescription()
    tiles.xSize, tiles.ySize, tiles.mode = 8, 8, mode
    exr(f"tiled-{n}-zip.exr", {"compression": C.ZIP_COMPRESSION, "type": C.tiledimage, "tiles": tiles}, crop)
# A data window offset inside a larger display window.
exr(
    "windows-none.exr",
    {"compression": C.NO_COMPRESSION, "type": C.scanlineimage,
     "dataWindow": (np.array([2, 1], dtype=np.int32), np.array([9, 4], dtype=np.int32)),
     "displayWindow": (np.array([0, 0], dtype=np.int32), np.array([15, 7], dtype=np.int32))},
    {k: np.ascontiguousarray(v[1:5, 2:10]) for k, v in crop.items()},
)
tmp = tempfile.mktemp(suffix=".exr")
C.File([C.Part(scan(C.ZIP_COMPRESSION), dict(crop), "beauty"), C.Part(scan(C.RLE_COMPRESSION), {"Y": crop["B"]}, "depth")]).write(tmp)
with open(tmp, "rb") as f:
    out("exr", "multipart.exr", f.read())
os.remove(tmp)


# --- Radiance HDR: flat and run-length encoded scan lines -------------------
def rgbe(p):
    p = [max(0.0, float(c)) if np.isfinite(c) else 0.0 for c in p]
    m = max(p)
    if m < 1e-32:
        return [0, 0, 0, 0]
    mant, e = np.frexp(m)
    s = mant * 256.0 / m
    return [min(255, int(c * s)) for c in p] + [int(e) + 128]


pix = [[rgbe(rgb[j, i]) for i in range(W)] for j in range(H)]
head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n" + f"-Y {H} +X {W}\n".encode()
out("hdr", "flat.hdr", head + bytes(v for row in pix for p in row for v in p))


def rle(values):
    o, i = bytearray(), 0
    while i < len(values):
        j = i
        while j < len(values) and j - i < 127 and values[j] == values[i]:
            j += 1
        if j - i >= 3:
            o += bytes([128 + j - i, values[i]])
            i = j
        else:
            k = i
            while k < len(values) and k - i < 128 and not (k + 2 < len(values) and values[k] == values[k + 1] == values[k + 2]):
                k += 1
            o += bytes([k - i]) + bytes(values[i:k])
            i = k
    return bytes(o)


body = b""
for row in pix:
    body += bytes([2, 2, W >> 8, W & 255]) + b"".join(rle([p[c] for p in row]) for c in range(4))
out("hdr", "rle.hdr", head + body)
out("hdr", "old-no-signature.hdr", f"FORMAT=32-bit_rle_rgbe\n\n-Y {H} +X {W}\n".encode() + bytes(v for row in pix for p in row for v in p))

# --- PNG and JPEG, through Pillow from the crop, sRGB encoded --------------
from PIL import Image as P

srgb = np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * np.power(np.clip(rgb / 4.0, 0.0031308, None), 1 / 2.4) - 0.055)
im = P.fromarray((np.clip(srgb, 0, 1) * 255 + 0.5).astype(np.uint8), "RGB")


def save(name, image, **kw):
    tmp = tempfile.mktemp(suffix=os.path.splitext(name)[1])
    image.save(tmp, **kw)
    with open(tmp, "rb") as f:
        out("png_jpeg", name, f.read())
    os.remove(tmp)


save("rgb8.png", im)
rgba = im.convert("RGBA")
save("rgba8.png", rgba)
save("grey8.png", im.convert("L"))
save("grey16.png", P.fromarray((np.clip(srgb[..., 1], 0, 1) * 65535).astype(np.uint16)))
save("palette.png", im.convert("P", palette=P.Palette.ADAPTIVE, colors=8))
save("grey-alpha.png", im.convert("LA"))
save("baseline.jpg", im, quality=80)
save("progressive.jpg", im, quality=80, progressive=True)
save("grey.jpg", im.convert("L"), quality=80)
save("subsampled.jpg", im, quality=80, subsampling=2)

# --- Meshes: a few triangles in every feature the readers handle ------------
out("obj", "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
out("obj", "normals-uv.obj",
    "# a tetrahedron\nmtllib m.mtl\no tet\ng side\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
    "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 -1\nvn 0 -1 0\nvn -1 0 0\nvn 0.577 0.577 0.577\n"
    "usemtl red\nf 1/1/1 3/3/1 2/2/1\nf 1//2 2//2 4//2\ns 1\nf -4/-3/-1 -1/-2/-1 -2/-1/-1\n"
    "o second\nv 2 0 0\nv 3 0 0\nv 2 1 0\nf 5 6 7\nl 1 2\np 3\n")
with open(os.path.join(ROOT, "meshes", "teapot.obj")) as f:
    lines = f.read().splitlines()
vs = [l for l in lines if l.startswith("v ")][:40]
fs = [l for l in lines if l.startswith("f ") and all(0 < int(t.split("/")[0]) <= 40 for t in l.split()[1:])][:40]
out("obj", "teapot-part.obj", "\n".join(vs + fs) + "\n")

# MTL: the bundled Cornell box's library, and one material with every key
# tobj reads (colours, scalars, texture maps with options, illum, unknown).
with open(os.path.join(ROOT, "meshes", "cornell_box.mtl"), "rb") as f:
    out("mtl", "cornell_box.mtl", f.read())
out("mtl", "every-key.mtl",
    "# every key\nnewmtl all\nKa 0.1 0.1 0.1\nKd 0.8 0.5 0.2\nKs 0.5 0.5 0.5\nKe 2 1.5 0.5\n"
    "Ns 96.0\nNi 1.45\nd 0.9\nTr 0.1\nillum 2\nmap_Ka ka.png\nmap_Kd -s 1 1 1 kd.png\n"
    "map_Ks ks.png\nmap_Ns ns.png\nmap_d d.png\nmap_Bump -bm 0.5 bump.png\nbump b.png\n"
    "norm n.png\nPr 0.5\n\nnewmtl second\nKd 1 1 1\n")

verts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]
faces = [(0, 2, 1), (0, 3, 2), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]
cols = [(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 0), (128, 128, 128)]
ply_head = lambda fmt, props: (
    f"ply\nformat {fmt} 1.0\ncomment pyramid\nelement vertex {len(verts)}\n" + props
    + f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
xyz = "property float x\nproperty float y\nproperty float z\n"
rgbp = "property uchar red\nproperty uchar green\nproperty uchar blue\n"
out("ply", "ascii.ply", ply_head("ascii", xyz + rgbp)
    + "".join(f"{v[0]} {v[1]} {v[2]} {c[0]} {c[1]} {c[2]}\n" for v, c in zip(verts, cols))
    + "".join(f"3 {a} {b} {c}\n" for a, b, c in faces))
nrm = "property float nx\nproperty float ny\nproperty float nz\n"
binv = b"".join(struct.pack("<6f", *v, 0.0, 0.0, 1.0) for v in verts)
binf = b"".join(struct.pack("<B3i", 3, *f) for f in faces)
out("ply", "binary.ply", ply_head("binary_little_endian", xyz + nrm).encode() + binv + binf)
quadf = b"".join(struct.pack("<B4i", 4, 0, 1, 2, 3) for _ in range(1)) + b"".join(struct.pack("<B3i", 3, *f) for f in faces[2:])
out("ply", "binary-quad-double.ply",
    (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(verts)}\nproperty double x\nproperty double y\nproperty double z\n"
     "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
     f"element face 5\nproperty list uchar uint vertex_indices\nelement edge 0\nproperty int vertex1\nend_header\n").encode()
    + b"".join(struct.pack("<3d4B", *v, *c, 255) for v, c in zip(verts, cols)) + quadf)

out("off", "plain.off", f"OFF\n# pyramid\n{len(verts)} {len(faces)} 0\n"
    + "".join(f"{v[0]} {v[1]} {v[2]}\n" for v in verts) + "".join(f"3 {a} {b} {c}\n" for a, b, c in faces))
out("off", "colour.off", f"COFF\n{len(verts)} 5 0\n"
    + "".join(f"{v[0]} {v[1]} {v[2]} {c[0]} {c[1]} {c[2]} 255\n" for v, c in zip(verts, cols))
    + "4 0 1 2 3\n" + "".join(f"3 {a} {b} {c}\n" for a, b, c in faces[2:]))
out("off", "normals.off", f"NOFF\n{len(verts)} {len(faces)} 0\n"
    + "".join(f"{v[0]} {v[1]} {v[2]} 0 0 1\n" for v in verts) + "".join(f"3 {a} {b} {c} 1 0 0\n" for a, b, c in faces))

# glTF: the pyramid with normals and colours under a two-node hierarchy, as
# .gltf with a data: URI and as GLB.
import base64

pos = b"".join(struct.pack("<3f", *v) for v in verts)
nor = b"".join(struct.pack("<3f", 0, 0, 1) for _ in verts)
col = b"".join(struct.pack("<3f", c[0] / 255, c[1] / 255, c[2] / 255) for c in cols)
idx = b"".join(struct.pack("<3H", *f) for f in faces)
buf = pos + nor + col + idx
n = len(verts)
doc = {
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"children": [1], "translation": [0, 1, 0]}, {"mesh": 0, "scale": [1, 1, -1]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "COLOR_0": 2}, "indices": 3, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]},
        {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC3"},
        {"bufferView": 3, "componentType": 5123, "count": 3 * len(faces), "type": "SCALAR"},
    ],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(nor)},
        {"buffer": 0, "byteOffset": 2 * len(pos), "byteLength": len(col)},
        {"buffer": 0, "byteOffset": 3 * len(pos), "byteLength": len(idx)},
    ],
    "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
}
out("gltf", "pyramid.gltf", json.dumps(doc))
strip = dict(doc, meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "mode": 5}]}])
out("gltf", "strip.gltf", json.dumps(strip))
glb_doc = json.loads(json.dumps(doc))
del glb_doc["buffers"][0]["uri"]
js = json.dumps(glb_doc).encode()
js += b" " * (-len(js) % 4)
binc = buf + b"\0" * (-len(buf) % 4)
glb = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(binc)) + struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(binc), b"BIN\0") + binc
out("gltf", "pyramid.glb", glb)

# A scene: the pyramid's positions quantized (normalized SHORT, padded to 8
# bytes a vertex, dequantized by the node) with UVs, placed by a node and
# three EXT_mesh_gpu_instancing instances, a 2x2 PNG base colour texture
# with KHR_texture_transform, an emissive MASK material, and a light of
# each kind under a turned parent; a GLB.
import zlib


def tiny_png(w, h, rgba):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    raw = b"".join(b"\0" + bytes(rgba[y * w * 4 : (y + 1) * w * 4]) for y in range(h))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


qpos = b"".join(struct.pack("<4h", *[round(c * 32767) for c in v], 0) for v in verts)
uvs = b"".join(struct.pack("<2f", v[0], v[2]) for v in verts)
png_bytes = tiny_png(2, 2, [255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255, 255, 255, 255, 0])
inst_t = struct.pack("<9f", 0, 0, 0, 2, 0, 0, 0, 0, 2)
inst_r = struct.pack("<12h", 0, 0, 0, 32767, 0, 23170, 0, 23170, 0, 0, 32767, 0)
parts = [qpos, uvs, idx, png_bytes, inst_t, inst_r]
views, sbuf = [], b""
for p in parts:
    views.append({"buffer": 0, "byteOffset": len(sbuf), "byteLength": len(p)})
    sbuf += p + b"\0" * (-len(p) % 4)
views[0]["byteStride"] = 8
scene_doc = {
    "asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_mesh_quantization", "EXT_mesh_gpu_instancing", "KHR_texture_transform",
                       "KHR_lights_punctual", "KHR_materials_emissive_strength", "EXT_unknown"],
    "extensionsRequired": ["KHR_mesh_quantization", "EXT_mesh_gpu_instancing"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"type": "point", "intensity": 50, "range": 4},
        {"type": "spot", "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
        {"type": "directional", "color": [1, 0.9, 0.8]}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2]}],
    "nodes": [
        {"mesh": 0, "translation": [0, 0.5, 0], "scale": [1, 1, 1]},
        {"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": 3, "ROTATION": 4}}}},
        {"rotation": [0.7071068, 0, 0, 0.7071068], "translation": [0, 3, 0], "children": [3, 4, 5]},
        {"extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"translation": [1, 0, 0], "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"scale": [-1, 1, 1], "extensions": {"KHR_lights_punctual": {"light": 2}}},
    ],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"alphaMode": "MASK", "alphaCutoff": 0.4, "emissiveFactor": [0.1, 0.1, 0],
                   "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}},
                   "pbrMetallicRoughness": {"metallicFactor": 0, "baseColorTexture": {"index": 0,
                       "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "rotation": 0.3, "scale": [2, 2]}}}}}],
    "samplers": [{"magFilter": 9728, "wrapS": 33648}],
    "images": [{"bufferView": 3, "mimeType": "image/png"}],
    "textures": [{"source": 0, "sampler": 0}],
    "accessors": [
        {"bufferView": 0, "componentType": 5122, "normalized": True, "count": n, "type": "VEC3", "min": [0, 0, 0], "max": [32767, 32767, 32767]},
        {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC2"},
        {"bufferView": 2, "componentType": 5123, "count": 3 * len(faces), "type": "SCALAR"},
        {"bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC3"},
        {"bufferView": 5, "componentType": 5122, "normalized": True, "count": 3, "type": "VEC4"},
    ],
    "bufferViews": views,
    "buffers": [{"byteLength": len(sbuf)}],
}
js = json.dumps(scene_doc).encode()
js += b" " * (-len(js) % 4)
out("gltf", "scene.glb", struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(sbuf))
    + struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(sbuf), b"BIN\0") + sbuf)

# --- Coefficient files and the engine formats `convert` reads back ----------
tmpdir = tempfile.mkdtemp()
crop_exr = os.path.join(tmpdir, "crop.exr")
C.File(scan(C.NO_COMPRESSION), dict(crop)).write(crop_exr)
def sh(*args):
    # Run in the scratch folder with relative names, so that the files'
    # provenance names "crop.exr", not a temporary path.
    args = [os.path.relpath(a, tmpdir) if a.startswith(tmpdir) else a for a in args]
    subprocess.run([SHLIGHT, "-q", *args], check=True, cwd=tmpdir)
for lmax in (1, 2):
    j = os.path.join(tmpdir, f"l{lmax}.json")
    sh("project", crop_exr, "--lmax", str(lmax), "-o", j)
    with open(j, "rb") as f:
        out("coefficients", f"shlight-l{lmax}.json", f.read())
# The binary form of `coefficients` (written from lmax 129 on; read at any
# lmax): the lmax 1 file with its rows as base64 of little-endian f64.
with open(os.path.join(tmpdir, "l1.json")) as f:
    doc = json.load(f)
rows = doc["coefficients"]
doc["coefficients"] = {"base64": base64.b64encode(struct.pack(f"<{3 * len(rows)}d", *[x for r in rows for x in r])).decode(),
                       "dtype": "<f8", "shape": [len(rows), 3]}
out("coefficients", "shlight-l1-binary.json", json.dumps(doc, separators=(",", ":")).encode())
j = os.path.join(tmpdir, "l2.json")
for fmt, ext in [("threejs", "json"), ("gltf", "gltf"), ("unity", "json"), ("filament", "txt")]:
    o = os.path.join(tmpdir, f"{fmt}.{ext}")
    sh("convert", j, "--format", fmt, "-o", o)
    with open(o, "rb") as f:
        out("coefficients", f"{fmt}.{ext}", f.read())
# GLB with EXT_lights_image_based: the .gltf's JSON in a GLB container.
with open(os.path.join(tmpdir, "gltf.gltf"), "rb") as f:
    js = f.read()
js += b" " * (-len(js) % 4)
out("coefficients", "gltf.glb", struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js)) + struct.pack("<I4s", len(js), b"JSON") + js)

# --- .shprt: the pyramid (as OFF) baked at lmax 1 and 2 ----------------------
mesh = os.path.join(CORPUS, "off", "plain.off")
for lmax, extra in [(1, []), (2, ["--albedo", "0.8,0.5,0.2"])]:
    o = os.path.join(tmpdir, f"l{lmax}.shprt")
    sh("prt", mesh, "--lmax", str(lmax), "--samples", "64", *extra, "-o", o)
    with open(o, "rb") as f:
        out("shprt", f"pyramid-l{lmax}.shprt", f.read())

# --- .shvol: the Cornell box's volume, 2x2x2 probes under the lmax 2 file ---
# Relightable (radiance, emitted, transfer) and static (radiance only); the
# static one at lmax 1 in a box reaching outside the room (the probes
# outside see the walls' backs: invalid at a low back-face fraction).
box = os.path.join(ROOT, "meshes", "cornell_box.obj")
for name, extra in [("relightable-l2", []),
                    ("static-l1-outside", ["--static", "--lmax", "1", "--bounds", "-0.3,0.1,-0.3:0.7,0.45,0.7", "--invalid-backfaces", "0.1"])]:
    o = os.path.join(tmpdir, f"{name}.shvol")
    sh("volume", box, "--env", j, "--resolution", "2x2x2", "--samples", "16", *extra, "-o", o)
    with open(o, "rb") as f:
        out("shvol", f"cornell-{name}.shvol", f.read())
shutil.rmtree(tmpdir)
