"""Make shlight's lightmap test scene with Blender and bake its truth per texel with Cycles.

Run (nothing at test time runs Blender; this regenerates the files):

    /path/to/bpy-venv/bin/python scripts/blender/make_lightmap_scenes.py tests/scenes

(the venv of make_scenes.py: bpy 5.0.1 and numpy). It writes, into OUTDIR:

- lightmap.glb: a 4 x 4 x 2.5 m room with a window, a textured floor, a
  table, a leaf cut-out (alphaMode MASK), three linked duplicates of one
  crate mesh, a point lamp and a sun through the window, exported with
  `bpy.ops.export_scene.gltf(export_format='GLB', export_lights=True)`, every
  other export setting left at its default. Every baked object has two UV
  maps: `UVMap` (TEXCOORD_0, textures) and `Lightmap` (TEXCOORD_1), a
  non-overlapping layout in [0, 1]^2 with margins;
- lightmap.truth.json: per baked object, per texel of its lightmap, the
  irradiance over pi (E/pi, W m^-2 sr^-1, linear Rec.709) that Cycles bakes
  (type DIFFUSE, passes DIRECT and INDIRECT, no COLOR), and the DIRECT pass
  alone, texel rows in glTF's UV orientation (row 0 at v = 0 of
  TEXCOORD_1, the top of Blender's image).

Options: `--samples N` the samples of each of the floor's two full bakes
(seeds 1 and 2), `--samples-other N` those of the other objects (the DIRECT
bakes take a quarter); `--only-export` writes the GLB and stops.

It reuses make_scenes.py's helpers (materials, lights, PNG drawing, the
closed forms and the GLB reader), imported from the same folder.
tests/scenes/README.md ("The lightmap scene") describes the files.
"""

import argparse
import json
import math
import os
import shutil
import struct
import sys
import time

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scenes as ms  # noqa: E402

TEXELS_PER_METRE = 20  # lightmap density on every baked object
MAX_SIDE = 128  # largest bake image side
GAP = 2  # texels between lightmap islands, and from the image's edge
SAMPLES_FLOOR = 24576  # the floor: the two seeds differ by about 1% per texel
SAMPLES_OTHER = 4096  # every other baked object
CRATE_LIFT = 0.01  # crates stand 1 cm above the floor: no face touches another object's face

# Blender coordinates (z up). The room: x, y in [-2, 2], z in [0, 2.5].
ROOM = (4.0, 4.0, 2.5)
WINDOW = ((-1.0, 0.5), (1.0, 1.5))  # in the -x wall: y in [-1, 1], z in [0.5, 1.5]
SUN_DIR = (2.0, 0.0, -1.0)  # along +x, 26.6 degrees down: lights the floor on x in [-1, 1]
SUN_STRENGTH = 5.0  # W/m^2
LAMP_AT = (0.5, -0.3, 2.1)
LAMP_POWER = 150.0  # W
TABLE = dict(cx=-0.7, cy=0.6, sx=1.0, sy=0.7, top=0.75, thick=0.04, leg=0.05, inset=0.06)
LEAF = dict(x=-1.6, y0=-0.9, y1=-0.1, z0=0.45, z1=1.25)  # a vertical cut-out quad facing the window
CRATES = [("Crate.A", 1.3, 1.3, 15.0), ("Crate.B", 1.2, -1.3, 40.0), ("Crate.C", -1.3, -1.5, 0.0)]
CRATE_SIZE = 0.4
TABLE_WOOD = (0.55, 0.38, 0.22)
CRATE_COLOUR = (0.45, 0.5, 0.6)


# ---------------------------------------------------------------------------
# Geometry


def rect_face_uvs(mesh, layer_name):
    """UVMap of a mesh of planar faces: each face's bounding rectangle in its
    own plane mapped onto [0, 1]^2 (for textures; only the floor's is used)."""
    layer = mesh.uv_layers.new(name=layer_name)
    for poly in mesh.polygons:
        pts = [mesh.vertices[mesh.loops[li].vertex_index].co for li in poly.loop_indices]
        a_axis, b_axis = plane_axes(poly.normal, pts)
        ab = [(p.dot(a_axis), p.dot(b_axis)) for p in pts]
        a0, a1 = min(a for a, _ in ab), max(a for a, _ in ab)
        b0, b1 = min(b for _, b in ab), max(b for _, b in ab)
        for li, (a, b) in zip(poly.loop_indices, ab):
            layer.data[li].uv = ((a - a0) / (a1 - a0), (b - b0) / (b1 - b0))
    return layer


def plane_axes(normal, pts):
    """Two unit axes spanning a face's plane: the first along the face's
    first edge, the second normal x first (so (a, b) keep the face's turn)."""
    n = Vector(normal).normalized()
    e = (pts[1] - pts[0]).normalized()
    return e, n.cross(e)


def lightmap_layout(mesh, density=TEXELS_PER_METRE):
    """The `Lightmap` UV layer: faces grouped into islands by plane (same
    normal and offset: a wall with a window is one island), each island
    mapped affinely at `density` texels per metre onto a rectangle of whole
    texels, islands packed on shelves GAP texels apart and GAP from the
    edge. Returns the image size (w, h) and the islands."""
    groups = {}
    for poly in mesh.polygons:
        n = poly.normal
        key = (round(n.x, 4), round(n.y, 4), round(n.z, 4), round(n.dot(mesh.vertices[poly.vertices[0]].co), 4))
        groups.setdefault(key, []).append(poly.index)
    islands = []
    for key, polys in groups.items():
        first = mesh.polygons[polys[0]]
        pts = [mesh.vertices[mesh.loops[li].vertex_index].co for li in first.loop_indices]
        a_axis, b_axis = plane_axes(first.normal, pts)
        coords = {}
        for pi in polys:
            for li in mesh.polygons[pi].loop_indices:
                p = mesh.vertices[mesh.loops[li].vertex_index].co
                coords[li] = (p.dot(a_axis), p.dot(b_axis))
        a0 = min(a for a, _ in coords.values())
        b0 = min(b for _, b in coords.values())
        ea = max(a for a, _ in coords.values()) - a0
        eb = max(b for _, b in coords.values()) - b0
        wa = max(1, math.ceil(ea * density - 1e-6))
        wb = max(1, math.ceil(eb * density - 1e-6))
        islands.append(dict(polys=polys, coords=coords, a0=a0, b0=b0, ea=ea, eb=eb, w=wa, h=wb))
    # Shelf packing, tallest first, shelves no wider than a square's side.
    islands.sort(key=lambda i: (-i["h"], -i["w"]))
    area = sum((i["w"] + GAP) * (i["h"] + GAP) for i in islands)
    limit = max(max(i["w"] for i in islands), int(math.ceil(math.sqrt(area))))
    x, y, shelf_h, width = 0, 0, 0, 0
    for isl in islands:
        if x > 0 and x + isl["w"] > limit:
            y += shelf_h + GAP
            x, shelf_h = 0, 0
        isl["x"], isl["y"] = GAP + x, GAP + y
        x += isl["w"] + GAP
        shelf_h = max(shelf_h, isl["h"])
        width = max(width, x - GAP)
    W = GAP + width + GAP
    H = GAP + y + shelf_h + GAP
    layer = mesh.uv_layers.new(name="Lightmap")
    for isl in islands:
        # Centre the island's extent in its rectangle of whole texels.
        ox = isl["x"] + (isl["w"] - isl["ea"] * density) / 2
        oy = isl["y"] + (isl["h"] - isl["eb"] * density) / 2
        for li, (a, b) in isl["coords"].items():
            layer.data[li].uv = ((ox + (a - isl["a0"]) * density) / W, (oy + (b - isl["b0"]) * density) / H)
    return (W, H), islands


def new_mesh(name, verts, faces, material):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(v) for v in verts], [], [tuple(f) for f in faces])
    mesh.materials.append(material)
    mesh.validate()
    mesh.update()
    return mesh


def link(name, mesh, location=(0, 0, 0), rot_z_deg=0.0):
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    obj.rotation_euler = (0, 0, math.radians(rot_z_deg))
    bpy.context.scene.collection.objects.link(obj)
    return obj


def baked_mesh(name, verts, faces, material):
    """A mesh with UVMap (per-face rectangles) and Lightmap (packed)."""
    mesh = new_mesh(name, verts, faces, material)
    rect_face_uvs(mesh, "UVMap")
    size, islands = lightmap_layout(mesh)
    uv = mesh.uv_layers
    uv["UVMap"].active_render = True
    uv.active = uv["UVMap"]
    mesh.update()
    return mesh, size, islands


def wall_faces(corner_lists):
    verts, faces = [], []
    for q in corner_lists:
        base = len(verts)
        verts.extend(q)
        faces.append(tuple(range(base, base + len(q))))
    return verts, faces


def build(s):
    """The scene (Blender coordinates). Returns the baked objects."""
    X, Y, H = ROOM[0] / 2, ROOM[1] / 2, ROOM[2]
    baked = []

    # Floor: one quad with the checker texture (TEXCOORD_0, affine over the
    # floor: u along +x, v along +y in Blender) and a lightmap.
    img = ms.load_png(s, "FloorChecker", ms.floor_texture_rows())
    floor_mat = ms.lambert("FloorChecker", None, image=img)
    nt = floor_mat.node_tree
    uvnode = nt.nodes.new("ShaderNodeUVMap")
    uvnode.uv_map = "UVMap"  # the texture reads UVMap whatever layer the bake rasterises
    tex = [n for n in nt.nodes if n.type == "TEX_IMAGE"][0]
    nt.links.new(uvnode.outputs["UV"], tex.inputs["Vector"])
    mesh, size, isl = baked_mesh("Floor", [(-X, -Y, 0), (X, -Y, 0), (X, Y, 0), (-X, Y, 0)],
                                 [(0, 1, 2, 3)], floor_mat)
    baked.append(dict(obj=link("Floor", mesh), size=size, islands=isl))

    grey = ms.lambert("Wall", ms.WALL_GREY)
    warm = ms.lambert("WarmWall", ms.WARM_WALL)
    # -x wall (normal +x) with the window: four quads, one lightmap island.
    v, f = wall_faces([[(-X, a, b) for (a, b) in q] for q in ms.rect_with_hole((-Y, 0), (Y, H), WINDOW)])
    mesh, size, isl = baked_mesh("WallWindow", v, f, grey)
    baked.append(dict(obj=link("WallWindow", mesh), size=size, islands=isl))
    # +y wall (normal -y), baked.
    v, f = wall_faces([[(-X, Y, 0), (X, Y, 0), (X, Y, H), (-X, Y, H)]])
    mesh, size, isl = baked_mesh("WallBack", v, f, grey)
    baked.append(dict(obj=link("WallBack", mesh), size=size, islands=isl))
    # +x wall (warm, normal -x) and -y wall (normal +y), and the ceiling: not baked.
    v, f = wall_faces([[(X, Y, 0), (X, -Y, 0), (X, -Y, H), (X, Y, H)]])
    link("WallWarm", new_mesh("WallWarm", v, f, warm))
    v, f = wall_faces([[(X, -Y, 0), (-X, -Y, 0), (-X, -Y, H), (X, -Y, H)]])
    link("WallFront", new_mesh("WallFront", v, f, grey))
    v, f = wall_faces([[(-X, -Y, H), (-X, Y, H), (X, Y, H), (X, -Y, H)]])
    link("Ceiling", new_mesh("Ceiling", v, f, ms.lambert("Ceiling", ms.CEILING_GREY)))

    # The table: a slab (baked) on four legs (open at both ends, so no leg
    # face lies on the floor or on the slab's underside).
    t = TABLE
    wood = ms.lambert("TableWood", TABLE_WOOD)
    v, f = ms.box(t["cx"], t["cy"], t["top"] - t["thick"] / 2, t["sx"], t["sy"], t["thick"])
    mesh, size, isl = baked_mesh("TableTop", v, f, wood)
    baked.append(dict(obj=link("TableTop", mesh), size=size, islands=isl))
    legs = []
    leg_h = t["top"] - t["thick"]
    for sx in (-1, 1):
        for sy in (-1, 1):
            lx = t["cx"] + sx * (t["sx"] / 2 - t["inset"])
            ly = t["cy"] + sy * (t["sy"] / 2 - t["inset"])
            bv, bf = ms.box(lx, ly, leg_h / 2, t["leg"], t["leg"], leg_h, bottom=False)
            legs.append((bv, [q for q in bf if q != (4, 5, 6, 7)]))  # drop the top face too
    v, f = ms.merge(legs)
    link("TableLegs", new_mesh("TableLegs", v, f, wood))

    # The leaf cut-out: a vertical quad in the sun's path between the window
    # and the table, alpha MASK (Round: the default cutoff 0.5).
    L = LEAF
    leaves = ms.load_png(s, "PlantLeaves", ms.plant_texture_rows())
    leaf_mat = ms.lambert("PlantLeaves", None, image=leaves, alpha_image=True)
    rows = ms.plant_texture_rows()
    n = len(rows)
    mask = [[1 if rows[n - 1 - j][i][3] else 0 for i in range(n)] for j in range(n)]
    corners = [(L["x"], L["y0"], L["z0"]), (L["x"], L["y1"], L["z0"]), (L["x"], L["y1"], L["z1"]),
               (L["x"], L["y0"], L["z1"])]
    ms.add_alpha_plane(s, "Leaf", corners, leaf_mat, mask, n)

    # Three linked duplicates of one crate mesh (one mesh datablock).
    c = CRATE_SIZE
    v, f = ms.box(0, 0, c / 2 + CRATE_LIFT, c, c, c)
    mesh, size, isl = baked_mesh("Crate", v, f, ms.lambert("Crate", CRATE_COLOUR))
    for name, x, y, deg in CRATES:
        baked.append(dict(obj=link(name, mesh, (x, y, 0), deg), size=size, islands=isl, instance_of="Crate"))

    ms.add_light(s, "Lamp", "POINT", LAMP_POWER, LAMP_AT)
    ms.add_light(s, "Sun", "SUN", SUN_STRENGTH, (-3.0, 0.0, 3.0), direction=SUN_DIR)
    return baked


# ---------------------------------------------------------------------------
# Texel positions by barycentric lookup in the Lightmap layer


def raster(uv, P, W, H):
    """Texel centres of a W x H image inside triangles with texel-unit UVs
    uv (n, 3, 2) (row r at v = (r + 0.5)/H); the point there by
    barycentric interpolation of P (n, 3, 3). Returns (inside, position,
    triangle index)."""
    inside = np.zeros((H, W), dtype=bool)
    pos = np.zeros((H, W, 3))
    which = np.full((H, W), -1)
    for k in range(len(uv)):
        t = uv[k]
        lo = np.floor(t.min(axis=0) - 0.5).astype(int)
        hi = np.ceil(t.max(axis=0) - 0.5).astype(int)
        xs = np.arange(max(lo[0], 0), min(hi[0], W - 1) + 1)
        ys = np.arange(max(lo[1], 0), min(hi[1], H - 1) + 1)
        if len(xs) == 0 or len(ys) == 0:
            continue
        cx, cy = np.meshgrid(xs + 0.5, ys + 0.5)
        d1, d2 = t[1] - t[0], t[2] - t[0]
        det = d1[0] * d2[1] - d1[1] * d2[0]
        if abs(det) < 1e-12:
            continue
        px, py = cx - t[0][0], cy - t[0][1]
        l1 = (px * d2[1] - py * d2[0]) / det
        l2 = (d1[0] * py - d1[1] * px) / det
        l0 = 1 - l1 - l2
        ok = (l0 >= -1e-9) & (l1 >= -1e-9) & (l2 >= -1e-9)
        rr, cc = (cy[ok] - 0.5).astype(int), (cx[ok] - 0.5).astype(int)
        inside[rr, cc] = True
        pos[rr, cc] = l0[ok, None] * P[k][0] + l1[ok, None] * P[k][1] + l2[ok, None] * P[k][2]
        which[rr, cc] = k
    return inside, pos, which


def texel_lookup(b):
    """Per texel of the object's lightmap (Blender rows, row 0 at v = 0):
    whether its centre lies in a triangle of the Lightmap layout, and the
    world position and normal there (Blender coordinates)."""
    obj = b["obj"]
    mesh = obj.data
    mesh.calc_loop_triangles()
    W, H = b["size"]
    layer = mesh.uv_layers["Lightmap"].data
    M = obj.matrix_world
    Nm = M.to_3x3().inverted().transposed()
    tris = list(mesh.loop_triangles)
    uv = np.array([[layer[li].uv[:] for li in t.loops] for t in tris]) * [W, H]
    P = np.array([[(M @ mesh.vertices[vi].co)[:] for vi in t.vertices] for t in tris])
    normals = np.array([(Nm @ t.normal).normalized()[:] for t in tris])
    inside, pos, which = raster(uv, P, W, H)
    nrm = np.where(inside[:, :, None], normals[np.maximum(which, 0)], 0.0)
    return inside, pos, nrm


def gltf_lookup(doc, binary, node_index, W, H):
    """The same from the GLB alone: texel centres over TEXCOORD_1 in glTF's
    orientation (row j at v_gltf = (j + 0.5)/H), positions from POSITION
    through the node's world transform, in glTF coordinates."""
    R, T = ms.node_world(doc)[node_index]
    uvs, Ps = [], []
    for prim in doc["meshes"][doc["nodes"][node_index]["mesh"]]["primitives"]:
        uv1 = accessor(doc, binary, prim["attributes"]["TEXCOORD_1"])
        pos = accessor(doc, binary, prim["attributes"]["POSITION"]) @ R.T + T
        idx = accessor(doc, binary, prim["indices"]).astype(int).reshape(-1, 3)
        uvs.append(uv1[idx] * [W, H])
        Ps.append(pos[idx])
    return raster(np.concatenate(uvs), np.concatenate(Ps), W, H)[:2]


# ---------------------------------------------------------------------------
# Baking

SENTINEL = -1.0  # written into every texel before a bake; texels left at it were not baked


def bake_object(b, seed, samples, passes):
    """Bake E/pi into a float image for one object (rasterised in its
    Lightmap layer); returns (H, W, 3) in Blender rows (row 0 at v = 0) and
    the coverage mask (texels the bake wrote)."""
    obj = b["obj"]
    W, H = b["size"]
    img = bpy.data.images.new("bake_%s_%d" % (obj.name, seed), W, H, alpha=True, float_buffer=True)
    img.pixels.foreach_set(np.full(W * H * 4, SENTINEL, dtype=np.float32))
    mat = obj.material_slots[0].material  # shared by linked duplicates: one object is baked at a time
    node = mat.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = img
    mat.node_tree.nodes.active = node
    sc = bpy.context.scene
    sc.cycles.samples = samples
    sc.cycles.seed = seed
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.bake(type="DIFFUSE", pass_filter=passes, margin=0, use_clear=False, uv_layer="Lightmap")
    px = np.empty(W * H * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    mat.node_tree.nodes.remove(node)
    bpy.data.images.remove(img)
    px = px.reshape(H, W, 4)
    covered = ~np.all(px == SENTINEL, axis=-1)
    return px[:, :, :3].astype(np.float64), covered


def rel_diff(a, b, covered):
    """Mean over covered texels of |a - b| / ((a + b) / 2), per channel,
    leaving out texels darker than 1e-3 of the object's brightest; `_lit`
    over texels brighter than a tenth of the object's median."""
    m = (a + b) / 2
    if not covered.any():
        return None
    top = m[covered].max()
    ok = covered[:, :, None] & (m > 1e-3 * top)
    r = np.abs(a - b)[ok] / m[ok]
    lum = m.mean(axis=-1)
    lit = covered[:, :, None] & (lum > 0.1 * np.median(lum[covered]))[:, :, None] & (m > 0)
    r_lit = np.abs(a - b)[lit] / m[lit]
    return dict(mean_relative_difference=ms.rnd(float(r.mean()), 4),
                mean_relative_difference_lit=ms.rnd(float(r_lit.mean()), 4),
                rms_relative_difference=ms.rnd(float(np.sqrt((r ** 2).mean())), 4),
                p99_relative_difference=ms.rnd(float(np.percentile(r, 99)), 4))


def grid_json(a, covered):
    """Rows in glTF's UV orientation (row 0 at v_gltf near 0, the top of
    Blender's image), 4 significant digits, null where not baked."""
    H, W = covered.shape
    out = []
    for r in range(H - 1, -1, -1):
        out.append([[float("%.4g" % x) + 0.0 for x in a[r, c]] if covered[r, c] else None for c in range(W)])
    return out


# ---------------------------------------------------------------------------
# Checks of the exported file


def glb_chunks(path):
    with open(path, "rb") as f:
        data = f.read()
    doc = ms.glb_json(path)
    clen = struct.unpack_from("<I", data, 12)[0]
    off = 20 + clen
    blen, btype = struct.unpack_from("<II", data, off)
    assert btype == 0x004E4942, path
    return doc, data[off + 8:off + 8 + blen]


def accessor(doc, binary, index):
    a = doc["accessors"][index]
    dtype = {5126: "<f4", 5125: "<u4", 5123: "<u2", 5121: "u1"}[a["componentType"]]
    ncomp = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    bv = doc["bufferViews"][a["bufferView"]]
    start = bv.get("byteOffset", 0) + a.get("byteOffset", 0)
    size = np.dtype(dtype).itemsize * ncomp
    stride = bv.get("byteStride", size)
    rows = [np.frombuffer(binary, dtype=dtype, count=ncomp, offset=start + i * stride) for i in range(a["count"])]
    out = np.array(rows, dtype=np.float64)
    return out if ncomp > 1 else out[:, 0]


def check_gltf(path, baked):
    """Node names, one mesh for the instances, TEXCOORD_1 = the Lightmap
    layer with v flipped, the floor's texture on TEXCOORD_0."""
    doc, binary = glb_chunks(path)
    problems = []
    nodes = {n.get("name"): n for n in doc["nodes"]}
    info = {}
    for b in baked:
        obj = b["obj"]
        n = nodes.get(obj.name)
        if n is None or "mesh" not in n:
            problems.append("no mesh node %s" % obj.name)
            continue
        gm = doc["meshes"][n["mesh"]]
        lm = obj.data.uv_layers["Lightmap"].data
        want = {(round(d.uv[0], 5), round(1 - d.uv[1], 5)) for d in lm}
        want0 = {(round(d.uv[0], 5), round(1 - d.uv[1], 5)) for d in obj.data.uv_layers["UVMap"].data}
        got, got0 = set(), set()
        for prim in gm["primitives"]:
            attrs = prim["attributes"]
            if "TEXCOORD_1" not in attrs or "TEXCOORD_0" not in attrs:
                problems.append("%s: attributes %s" % (obj.name, sorted(attrs)))
                continue
            got |= {(round(u, 5), round(v, 5)) for u, v in accessor(doc, binary, attrs["TEXCOORD_1"])}
            got0 |= {(round(u, 5), round(v, 5)) for u, v in accessor(doc, binary, attrs["TEXCOORD_0"])}
        if got != want:
            problems.append("%s: TEXCOORD_1 is not Lightmap with v flipped" % obj.name)
        if got0 != want0:
            problems.append("%s: TEXCOORD_0 is not UVMap with v flipped" % obj.name)
        info[obj.name] = dict(node=n["name"], mesh_index=n["mesh"], mesh=gm.get("name"),
                              translation=n.get("translation"), rotation=n.get("rotation"))
    crates = {info[b["obj"].name]["mesh_index"] for b in baked if b.get("instance_of") and b["obj"].name in info}
    if len(crates) != 1:
        problems.append("the crates use meshes %s" % sorted(crates))
    for m in doc.get("materials", []):
        tex = m.get("pbrMetallicRoughness", {}).get("baseColorTexture")
        if tex is not None and tex.get("texCoord", 0) != 0:
            problems.append("material %s reads texCoord %s" % (m.get("name"), tex.get("texCoord")))
    return problems, info, doc


# ---------------------------------------------------------------------------
# The closed form on the floor


def closed_form_check(s, floor, direct, covered_all):
    """Cycles' DIRECT bake against P/(4 pi) cos/d^2/pi + S cos/pi at floor
    texels whose 3 x 3 neighbourhood is baked and sees each light alike
    (all lit or all shadowed, ray casts through the leaf's mask)."""
    inside, pos, nrm = floor["lookup"]
    H, W = inside.shape
    depsgraph = bpy.context.evaluated_depsgraph_get()
    e = np.zeros((H, W))
    lit = {L["name"]: np.zeros((H, W), dtype=bool) for L in s.lights}
    for r in range(H):
        for c in range(W):
            if not inside[r, c]:
                continue
            n = Vector(nrm[r, c])
            p = Vector(pos[r, c]) + n * 1e-4
            for L in s.lights:
                if L["type"] == "SUN":
                    to_light, dist, strength = -L["direction"], 1e4, L["power"]
                else:
                    d = L["location"] - p
                    dist = d.length
                    to_light = d / dist
                    strength = L["power"] / (4 * math.pi) / (dist * dist)
                cos_n = to_light.dot(n)
                if cos_n <= 0 or not ms.visible(s, depsgraph, p, to_light, dist):
                    continue
                lit[L["name"]][r, c] = True
                e[r, c] += strength * cos_n / math.pi
    ok = inside & covered_all
    for m in lit.values():
        same = np.ones((H, W), dtype=bool)
        pad = np.pad(m, 1, mode="edge")
        padc = np.pad(ok, 1, constant_values=False)
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                same &= pad[1 + dr:1 + dr + H, 1 + dc:1 + dc + W] == m
                ok &= padc[1 + dr:1 + dr + H, 1 + dc:1 + dc + W]
        ok &= same
    ok &= lit["Lamp"]
    ratio = direct.mean(axis=-1)[ok] / e[ok]
    sun = lit["Sun"][ok]
    res = dict(texels=int(ok.sum()), min=float(ratio.min()), median=float(np.median(ratio)),
               max=float(ratio.max()), sunlit_texels=int(sun.sum()),
               sunlit_median=float(np.median(ratio[sun])) if sun.any() else None,
               lamp_only_median=float(np.median(ratio[~sun])) if (~sun).any() else None)
    # A few texels by name: nearest the lamp, and a sunlit one.
    picks = []
    rr, cc = np.nonzero(ok)
    lamp = s.lights[0]["location"]
    d = np.linalg.norm(pos[rr, cc] - np.array(lamp[:]), axis=1)
    order = list(np.argsort(d)[:2])
    sl = np.nonzero(lit["Sun"][rr, cc])[0]
    if len(sl):
        order.append(sl[len(sl) // 2])
    order.append(int(np.argmax(d)))
    for k in order:
        r, c = rr[k], cc[k]
        picks.append(dict(texel_gltf=[int(c), int(H - 1 - r)], position=[ms.rnd(x, 5) for x in ms.to_gltf(pos[r, c])],
                          closed_form=ms.rnd(e[r, c], 5), cycles_direct=[ms.rnd(x, 5) for x in direct[r, c]],
                          sunlit=bool(lit["Sun"][r, c])))
    res["examples"] = picks
    return res


# ---------------------------------------------------------------------------


def describe_islands(b):
    """Each island: its faces' plane in glTF coordinates and where its texels lie."""
    out = []
    W, H = b["size"]
    for isl in b["islands"]:
        out.append(dict(texels_gltf=[isl["x"], H - isl["y"] - isl["h"], isl["w"], isl["h"]],
                        faces=len(isl["polys"]), extent_m=[ms.rnd(isl["ea"], 4), ms.rnd(isl["eb"], 4)]))
    return out


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("--samples", type=int, default=SAMPLES_FLOOR, help="samples of each floor bake")
    ap.add_argument("--samples-other", type=int, default=SAMPLES_OTHER,
                    help="samples of each bake of the other objects")
    ap.add_argument("--only-export", action="store_true")
    ap.add_argument("--objects", default=None, help="bake only these objects (comma-separated; for trials)")
    ap.add_argument("--dump", default=None, help="also save each object's raw bakes here (.npz)")
    args = ap.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    t0 = time.time()
    s = ms.reset("lightmap")
    ms.set_world(s, None)
    baked = build(s)
    glb = os.path.join(args.outdir, "lightmap.glb")
    ms.export_glb(glb)
    summary = ms.summarize_glb(glb)
    problems = ms.check_export(s, summary)
    more, info, doc = check_gltf(glb, baked)
    problems += more
    print("[lightmap] export %d bytes, extensionsUsed %s; meshes used by nodes %s"
          % (summary["bytes"], summary["extensionsUsed"], json.dumps(summary["mesh_nodes"])))
    print("[lightmap] baked nodes %s" % json.dumps(info))
    for m in summary["materials"]:
        print("[lightmap] material %s" % json.dumps(m))
    if problems:
        raise SystemExit("[lightmap] export problems: %s" % "; ".join(problems))
    for b in baked:
        b["lookup"] = texel_lookup(b)
        # The glTF side: texel rows flipped (glTF row j is Blender row H - 1 - j),
        # positions from the GLB, must be the same texels at the same places.
        W, H = b["size"]
        ni = [i for i, n in enumerate(doc["nodes"]) if n.get("name") == info[b["obj"].name]["node"]][0]
        g_in, g_pos = gltf_lookup(doc, glb_chunks(glb)[1], ni, W, H)
        b_in, b_pos = b["lookup"][0][::-1], np.array([[ms.to_gltf(p) for p in row] for row in b["lookup"][1][::-1]])
        if (g_in != b_in).any():
            raise SystemExit("[lightmap] %s: texels inside TEXCOORD_1 differ from the Lightmap layer's" % b["obj"].name)
        err = float(np.abs(g_pos - b_pos)[g_in].max())
        if err > 1e-5:
            raise SystemExit("[lightmap] %s: texel positions from the GLB differ by %g m" % (b["obj"].name, err))
        print("[lightmap] %s: %d x %d texels, %d centres inside the layout; the GLB's TEXCOORD_1 puts them "
              "at the same glTF positions (largest difference %.1e m)"
              % (b["obj"].name, W, H, int(b["lookup"][0].sum()), err))
    if args.only_export:
        return
    objects = []
    floor_check = None
    times = []
    for b in baked:
        name = b["obj"].name
        if args.objects and name not in args.objects.split(","):
            continue
        runs = {}
        samples = args.samples if name == "Floor" else args.samples_other
        dsamples = max(samples // 4, 16)
        for kind, passes, n in (("full", {"DIRECT", "INDIRECT"}, samples), ("direct", {"DIRECT"}, dsamples)):
            res = []
            for seed in (1, 2):
                t1 = time.time()
                res.append(bake_object(b, seed, n, passes))
                dt = time.time() - t1
                times.append(dict(object=name, kind=kind, seed=seed, samples=n, seconds=round(dt, 1)))
                print("[lightmap] %s %s seed %d: %d samples, %.1f s" % (name, kind, seed, n, dt), flush=True)
            runs[kind] = res
        covs = [c for k in runs for _, c in runs[k]]
        covered = covs[0].copy()
        for c in covs[1:]:
            covered &= c
        union = np.zeros_like(covered)
        for c in covs:
            union |= c
        inside = b["lookup"][0]
        (fa, _), (fb, _) = runs["full"]
        (da, _), (db, _) = runs["direct"]
        if args.dump:
            os.makedirs(args.dump, exist_ok=True)
            np.savez_compressed(os.path.join(args.dump, name + ".npz"), fa=fa, fb=fb, da=da, db=db, covered=covered,
                                pos=b["lookup"][1])
        full = (fa + fb) / 2
        direct = (da + db) / 2
        noise = rel_diff(fa, fb, covered)
        noise_d = rel_diff(da, db, covered)
        print("[lightmap] %s: %d texels baked (bakes disagree on %d; baked but centre outside the layout %d, "
              "centre inside but not baked %d); noise %s, direct %s"
              % (name, int(covered.sum()), int((union & ~covered).sum()), int((covered & ~inside).sum()),
                 int((inside & ~covered).sum()), noise, noise_d), flush=True)
        rec = dict(node=info[name]["node"], mesh=info[name]["mesh"], blender_object=name,
                   size=list(b["size"]), texels_per_metre=TEXELS_PER_METRE, baked_texels=int(covered.sum()),
                   samples=samples, samples_direct=dsamples,
                   noise=noise, noise_direct=noise_d, islands=describe_islands(b))
        if b.get("instance_of"):
            rec["instance_of"] = info[name]["mesh"]
            rec["note"] = ("a linked duplicate: its lightmap UVs are the mesh's, the same for every node "
                           "using mesh %r; the texels hold this node's light" % info[name]["mesh"])
        rec["e_over_pi"] = grid_json(full, covered)
        rec["e_over_pi_direct"] = grid_json(direct, covered)
        objects.append(rec)
        if name == "Floor":
            floor_check = closed_form_check(s, b, direct, covered)
            print("[lightmap] floor closed form: %s" % json.dumps(floor_check), flush=True)
    out = {
        "scene": "lightmap",
        "description": ("A 4 x 4 x 2.5 m room (glTF x, z in [-2, 2], y in [0, 2.5]) with a 2 x 1 m window in "
                        "the x = -2 wall, a checker-textured floor, a table, a leaf cut-out (alphaMode MASK) "
                        "in the sun's path, three nodes using one crate mesh, a 150 W point lamp and a "
                        "5 W/m^2 sun through the window; world black."),
        "blender": bpy.app.version_string, "gltf_exporter": ms.exporter_version(),
        "samples": ("per object (its samples and samples_direct): each of the two seeds' bakes takes that many; "
                    "the DIRECT-only bakes a quarter"),
        "seeds": [1, 2], "max_bounces": ms.MAX_BOUNCES,
        "bake": ("Cycles CPU, bake type DIFFUSE, pass_filter {DIRECT, INDIRECT} (e_over_pi) or {DIRECT} "
                 "(e_over_pi_direct), no COLOR, margin 0, rasterised in the Lightmap UV layer (TEXCOORD_1); "
                 "no denoising, adaptive sampling off, no clamping; each value is the mean of the two seeds"),
        "units": "E/pi, W m^-2 sr^-1, linear Rec.709",
        "coordinates": "glTF (y up, metres): a Blender point (x, y, z) is (x, z, -y)",
        "texels": ("e_over_pi[j][i] is texel (i, j) of a size[0] x size[1] image over TEXCOORD_1: its centre is "
                   "(u, v) = ((i + 0.5)/size[0], (j + 0.5)/size[1]) in glTF's UV convention (row j = 0 at v = 0; "
                   "the exporter writes v_gltf = 1 - v_blender, so this is the top row of Blender's image); "
                   "null where the bake wrote nothing (no triangle covers the texel's centre)"),
        "sampling": ("Cycles jitters each sample uniformly over the texel's footprint (a box of one texel, "
                     "not the pixel filter), retried until it falls inside the texel centre's triangle (10 "
                     "tries, then the centre); the first sample is at the centre. So a value is the mean "
                     "over the part of the texel inside that triangle."),
        "noise": ("per object, over baked texels (and channels) brighter than 1e-3 of the object's brightest: "
                  "the mean, RMS and 99th percentile of |a - b| / ((a + b)/2) between the two seeds' bakes a "
                  "and b; the standard error of a stored value (their mean) is about |a - b|/2"),
        "world": None,
        "lights": ms.light_records(s, summary),
        "floor_closed_form": floor_check,
        "bake_seconds": times,
        "objects": objects,
    }
    path = os.path.join(args.outdir, "lightmap.truth.json")
    ms.write_atomic(path, pretty(out).encode("utf-8"))
    shutil.rmtree(s.scratch, ignore_errors=True)
    print("[lightmap] wrote %s (%d bytes); all done in %.0f s" % (path, os.path.getsize(path), time.time() - t0))


def pretty(doc):
    """Indented JSON, but each texel row on one line."""
    def enc(x, ind):
        pad = " " * ind
        if isinstance(x, dict):
            items = ["%s %s: %s" % (pad, json.dumps(k), enc(v, ind + 1)) for k, v in x.items()]
            return "{\n" + ",\n".join(items) + "\n" + pad + "}"
        if isinstance(x, list) and x and isinstance(x[0], list) and x[0] and \
                (x[0][0] is None or isinstance(x[0][0], list)):
            return "[\n" + ",\n".join(pad + " " + json.dumps(r, separators=(",", ":")) for r in x) + "\n" + pad + "]"
        if isinstance(x, list) and x and isinstance(x[0], dict):
            return "[\n" + ",\n".join(pad + " " + enc(v, ind + 1) for v in x) + "\n" + pad + "]"
        return json.dumps(x, separators=(", ", ": "))
    return enc(doc, 0) + "\n"


if __name__ == "__main__":
    main(sys.argv[1:])
