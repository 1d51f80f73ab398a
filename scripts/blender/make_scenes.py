"""Make shlight's glTF test scenes with Blender and bake their truth with Cycles.

Run (nothing at test time runs Blender; this regenerates tests/scenes/):

    python3.11 -m venv /path/to/bpy-venv
    /path/to/bpy-venv/bin/pip install bpy==5.0.1 numpy
    /path/to/bpy-venv/bin/python scripts/blender/make_scenes.py tests/scenes \
        --example meshes/room.glb

Made with Blender 5.0.1 (the PyPI `bpy` module 5.0.1, Python 3.11), its glTF
exporter io_scene_gltf2 5.0.21, and numpy 1.26.4. A full run takes about
1 h 50 min on two busy CPU cores (Cycles on the CPU with fixed seeds: reruns
give the same bytes). tests/scenes/README.md describes the scenes.

Every scene is built from nothing: geometry from coordinates in this file,
textures drawn by this file as PNG images and packed into the GLB. For each
scene NAME the script writes, into OUTDIR:

- NAME.glb: `bpy.ops.export_scene.gltf(export_format='GLB',
  export_lights=True)`, every other export setting left at its default;
- NAME.truth.json: the irradiance over pi (E/pi, W m^-2 sr^-1) that Cycles
  bakes on the scene's bake targets (the floor, and the ceiling in
  `texture`), averaged over blocks of texels, at glTF positions.

Options: `--only a,b` makes some scenes; `--samples N` the Cycles samples of
each of the two bakes (seeds 1 and 2) averaged into the truth; `--example
PATH` copies room.glb to PATH as well.

Coordinates: Blender is z-up; the exporter (+Y up, its default) maps a
Blender point (x, y, z) to glTF (x, z, -y). Everything this script writes in
a truth file is in glTF coordinates.
"""

import argparse
import json
import math
import os
import shutil
import struct
import sys
import tempfile
import time
import zlib

import bpy
import numpy as np
from mathutils import Vector

# ---------------------------------------------------------------------------
# Settings

BLOCK = 8  # texels averaged per block side
TEXELS_PER_METRE = 32  # bake image resolution on the targets (0.25 m blocks)
MAX_BOUNCES = 32
WALL_GREY = (0.6, 0.6, 0.6)
WARM_WALL = (0.7, 0.5, 0.35)  # the +x wall, so colour bleeds
CEILING_GREY = (0.7, 0.7, 0.7)
FLOOR_GREY = (0.5, 0.5, 0.5)
CHAIR_WOOD = (0.6, 0.4, 0.25)
SKY = (0.6, 0.7, 0.9)
W_TO_LM = 683.0  # the exporter's watts-to-lumens factor


def to_gltf(p):
    """Blender (x, y, z) to glTF (x, z, -y)."""
    return [float(p[0]), float(p[2]), float(-p[1])]


def write_atomic(path, data):
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


# ---------------------------------------------------------------------------
# PNG images drawn here


def png_bytes(rgba_rows):
    """An 8-bit RGBA PNG from rows (top row first) of (r, g, b, a) bytes."""
    h = len(rgba_rows)
    w = len(rgba_rows[0])
    raw = b"".join(b"\x00" + bytes(v for px in row for v in px) for row in rgba_rows)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


# Floor checker: 8 x 8 squares, two colours on the x < 0 half (u < 0.5),
# two others on the x > 0 half, so light bounced off the floor is coloured
# differently on each side. sRGB bytes.
FLOOR_COLOURS = {"red": (200, 60, 40), "yellow": (230, 200, 90),
                 "blue": (50, 90, 200), "green": (70, 170, 80)}
FLOOR_TEX = 64


def floor_texture_rows():
    rows = []
    n = FLOOR_TEX
    for r in range(n):  # r = 0 is the top row: v near 1
        v_cell = (n - 1 - r) // (n // 8)
        row = []
        for c in range(n):
            u_cell = c // (n // 8)
            even = (u_cell + v_cell) % 2 == 0
            if c < n // 2:
                col = FLOOR_COLOURS["red"] if even else FLOOR_COLOURS["yellow"]
            else:
                col = FLOOR_COLOURS["blue"] if even else FLOOR_COLOURS["green"]
            row.append(col + (255,))
        rows.append(row)
    return rows


# The cut-out scene's leaf: a pixel-art leaf on a 12 x 12 grid of cells
# (8 x 8 texels each, so linear and nearest filtering cut at the same cell
# edges), alpha exactly 0 or 1. Under the straight-down sun each cell
# shades exactly one 0.25 m block of the floor's truth, so no block
# straddles the shadow's edge.
LEAF_CELLS = 12
LEAF_TEX = 96


def leaf_cell_mask():
    """mask[j][i]: cell i along u, j along v (j = 0 at v = 0)."""
    n = LEAF_CELLS
    mask = []
    ang = math.radians(40.0)
    ca, sa = math.cos(ang), math.sin(ang)
    for j in range(n):
        row = []
        for i in range(n):
            x = (i + 0.5) / n - 0.5
            y = (j + 0.5) / n - 0.5
            a = x * ca + y * sa  # along the leaf
            b = -x * sa + y * ca  # across it
            inside = (a / 0.5) ** 2 + (b / 0.3) ** 2 <= 1.0
            vein = abs(b) < 0.05 and -0.25 < a < 0.3  # a transparent midrib
            row.append(1 if inside and not vein else 0)
        mask.append(row)
    return mask


def leaf_texture_rows(mask):
    n = LEAF_TEX
    per = n // LEAF_CELLS
    rows = []
    for r in range(n):
        j = (n - 1 - r) // per
        row = []
        for c in range(n):
            i = c // per
            shade = 60 + 40 * ((i + j) % 2)
            row.append((40, 120 + shade // 2, 30, 255) if mask[j][i] else (0, 0, 0, 0))
        rows.append(row)
    return rows


def plant_texture_rows():
    """The room's plant: leaves as smooth ellipses, alpha exactly 0 or 1."""
    n = 128
    leaves = [(0.5, 0.25, 90, 0.06, 0.22), (0.32, 0.45, 130, 0.06, 0.2), (0.68, 0.45, 50, 0.06, 0.2),
              (0.25, 0.7, 150, 0.05, 0.17), (0.75, 0.7, 30, 0.05, 0.17), (0.5, 0.6, 95, 0.05, 0.2),
              (0.42, 0.85, 110, 0.05, 0.13), (0.6, 0.86, 70, 0.05, 0.13)]
    rows = []
    for r in range(n):
        v = 1.0 - (r + 0.5) / n
        row = []
        for c in range(n):
            u = (c + 0.5) / n
            on = False
            for (cu, cv, deg, wid, length) in leaves:
                a = math.radians(deg)
                du, dv = u - cu, v - cv
                along = du * math.cos(a) + dv * math.sin(a)
                across = -du * math.sin(a) + dv * math.cos(a)
                if (along / length) ** 2 + (across / wid) ** 2 <= 1.0:
                    on = True
            stem = abs(u - 0.5) < 0.012 and v < 0.6
            row.append((50, 140, 45, 255) if on or stem else (0, 0, 0, 0))
        rows.append(row)
    return rows


# ---------------------------------------------------------------------------
# Blender scene building


class Scene:
    """What the script knows about the scene it builds (Blender coordinates)."""

    def __init__(self, name):
        self.name = name
        self.lights = []  # dicts describing delta lights, for the closed forms
        self.targets = []  # (object, corners, normal, material)
        self.alpha_planes = {}  # object name -> (origin, eu, ev, mask[j][i] in cells, cells)
        self.world = None
        self.scratch = tempfile.mkdtemp(prefix="shlight-scenes-")


def reset(scene_name):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.name = scene_name
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.device = "CPU"
    c.use_denoising = False
    c.use_adaptive_sampling = False
    c.max_bounces = MAX_BOUNCES
    c.diffuse_bounces = MAX_BOUNCES
    c.glossy_bounces = MAX_BOUNCES
    c.transmission_bounces = MAX_BOUNCES
    c.transparent_max_bounces = MAX_BOUNCES
    c.volume_bounces = 0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.light_sampling_threshold = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    sc.render.bake.margin = 0
    return Scene(scene_name)


def set_world(s, colour):
    """A constant world; black (None) means no world light."""
    w = bpy.data.worlds.new("World")
    bg = w.node_tree.nodes["Background"]
    c = colour if colour is not None else (0.0, 0.0, 0.0)
    bg.inputs["Color"].default_value = (c[0], c[1], c[2], 1.0)
    bg.inputs["Strength"].default_value = 1.0
    bpy.context.scene.world = w
    s.world = list(colour) if colour is not None else None


def lambert(name, colour=None, image=None, alpha_image=False, alpha_cutoff=None):
    """A Principled BSDF made Lambertian: Specular IOR Level 0, roughness 1."""
    m = bpy.data.materials.new(name)
    nt = m.node_tree
    bsdf = nt.nodes["Principled BSDF"]
    bsdf.inputs["Specular IOR Level"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Metallic"].default_value = 0.0
    if colour is not None:
        bsdf.inputs["Base Color"].default_value = (colour[0], colour[1], colour[2], 1.0)
    if image is not None:
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = image
        tex.interpolation = "Closest"
        nt.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
        if alpha_image and alpha_cutoff is None:
            # Alpha -> Round -> Alpha: the exporter writes alphaMode MASK
            # and leaves alphaCutoff out (the default, 0.5).
            rnd = nt.nodes.new("ShaderNodeMath")
            rnd.operation = "ROUND"
            nt.links.new(tex.outputs["Alpha"], rnd.inputs[0])
            nt.links.new(rnd.outputs[0], bsdf.inputs["Alpha"])
        elif alpha_image:
            # Alpha -> 1 - (Alpha < cutoff) -> Alpha: alphaMode MASK with
            # this alphaCutoff.
            less = nt.nodes.new("ShaderNodeMath")
            less.operation = "LESS_THAN"
            nt.links.new(tex.outputs["Alpha"], less.inputs[0])
            less.inputs[1].default_value = alpha_cutoff
            sub = nt.nodes.new("ShaderNodeMath")
            sub.operation = "SUBTRACT"
            sub.inputs[0].default_value = 1.0
            nt.links.new(less.outputs[0], sub.inputs[1])
            nt.links.new(sub.outputs[0], bsdf.inputs["Alpha"])
        # Either way Cycles sees alpha exactly 0 or 1: the texture's alpha
        # is 0 or 1 and it is sampled without interpolation.
    return m


def load_png(s, name, rows):
    path = os.path.join(s.scratch, name + ".png")
    with open(path, "wb") as f:
        f.write(png_bytes(rows))
    img = bpy.data.images.load(path)
    img.name = name
    img.pack()
    return img


def mesh_object(name, verts, faces, materials, face_mats=None, uvs=None, mesh=None):
    """An object at the origin whose mesh holds world coordinates."""
    if mesh is None:
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([tuple(v) for v in verts], [], [tuple(f) for f in faces])
        for m in materials:
            mesh.materials.append(m)
        if face_mats is not None:
            for poly, mi in zip(mesh.polygons, face_mats):
                poly.material_index = mi
        if uvs is not None:
            layer = mesh.uv_layers.new(name="UVMap")
            for poly in mesh.polygons:
                for li in poly.loop_indices:
                    vi = mesh.loops[li].vertex_index
                    layer.data[li].uv = uvs[vi]
        mesh.validate()
        mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def quad(name, p0, p1, p2, p3, material):
    """A rectangle with corners p0..p3 (counter-clockwise seen from its
    front) and UV (0,0), (1,0), (1,1), (0,1) at them: the UV map is affine."""
    return mesh_object(name, [p0, p1, p2, p3], [(0, 1, 2, 3)], [material],
                       uvs=[(0, 0), (1, 0), (1, 1), (0, 1)])


def rect_with_hole(lo, hi, hole):
    """Quads covering [lo0, hi0] x [lo1, hi1] minus the rectangle hole,
    as lists of four 2D corners (counter-clockwise in the (a, b) plane)."""
    (a0, b0), (a1, b1) = lo, hi
    if hole is None:
        rects = [(a0, b0, a1, b1)]
    else:
        (ha0, hb0), (ha1, hb1) = hole
        rects = [(a0, b0, a1, hb0), (a0, hb1, a1, b1), (a0, hb0, ha0, hb1), (ha1, hb0, a1, hb1)]
    return [[(r[0], r[1]), (r[2], r[1]), (r[2], r[3]), (r[0], r[3])] for r in rects]


def build_room(s, size_x, size_y, height, window=None, skylight=None, floor_material=None,
               ceiling_target=False):
    """A closed room [-X, X] x [-Y, Y] x [0, H]: the floor and the ceiling
    are objects of their own (bake targets have affine UV maps), the walls
    one object (grey, the +x wall warm) with an optional window in the -x
    wall: window = ((y0, z0), (y1, z1)). skylight = ((x0, y0), (x1, y1)) is a
    hole in the ceiling."""
    X, Y, H = size_x / 2, size_y / 2, height
    grey = lambert("Wall", WALL_GREY)
    warm = lambert("WarmWall", WARM_WALL)
    verts, faces, mats = [], [], []

    def add(corners3, mi):
        base = len(verts)
        verts.extend(corners3)
        faces.append((base, base + 1, base + 2, base + 3))
        mats.append(mi)

    # -x wall (normal +x): plane coordinates (y, z), counter-clockwise seen from +x.
    for q in rect_with_hole((-Y, 0), (Y, H), window):
        add([(-X, a, b) for (a, b) in q], 0)
    # +x wall (normal -x): seen from -x, ccw order runs y downwards.
    add([(X, Y, 0), (X, -Y, 0), (X, -Y, H), (X, Y, H)], 1)
    # -y wall (normal +y)
    add([(X, -Y, 0), (-X, -Y, 0), (-X, -Y, H), (X, -Y, H)], 0)
    # +y wall (normal -y)
    add([(-X, Y, 0), (X, Y, 0), (X, Y, H), (-X, Y, H)], 0)
    mesh_object("Walls", verts, faces, [grey, warm], face_mats=mats)

    fm = floor_material if floor_material is not None else lambert("Floor", FLOOR_GREY)
    floor = quad("Floor", (-X, -Y, 0), (X, -Y, 0), (X, Y, 0), (-X, Y, 0), fm)
    s.targets.append(dict(obj=floor, origin=Vector((-X, -Y, 0)), eu=Vector((2 * X, 0, 0)),
                          ev=Vector((0, 2 * Y, 0)), normal=Vector((0, 0, 1))))

    cm = lambert("Ceiling", CEILING_GREY)
    if skylight is None:
        # Seen from below (normal -z): corners run clockwise seen from above.
        ceiling = quad("Ceiling", (-X, -Y, H), (-X, Y, H), (X, Y, H), (X, -Y, H), cm)
        if ceiling_target:
            # UV (0,0) at (-X,-Y), u along +y, v along +x (the quad's order).
            s.targets.append(dict(obj=ceiling, origin=Vector((-X, -Y, H)), eu=Vector((0, 2 * Y, 0)),
                                  ev=Vector((2 * X, 0, 0)), normal=Vector((0, 0, -1))))
    else:
        verts, faces = [], []
        for q in rect_with_hole((-X, -Y), (X, Y), skylight):
            base = len(verts)
            verts.extend([(a, b, H) for (a, b) in reversed(q)])
            faces.append((base, base + 1, base + 2, base + 3))
        mesh_object("Ceiling", verts, faces, [cm])
    return X, Y, H


def add_light(s, name, kind, power, location, direction=None, spot_size=None, spot_blend=None):
    """A Blender light with no radius (a true point/spot) or angle (a sun).
    power: watts (point, spot) or W/m^2 (sun). direction: where the light
    shines, Blender coordinates."""
    data = bpy.data.lights.new(name, kind)
    data.energy = power
    if kind == "SUN":
        data.angle = 0.0
    else:
        data.shadow_soft_size = 0.0
    if kind == "SPOT":
        data.spot_size = spot_size
        data.spot_blend = spot_blend
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    if direction is not None:
        obj.rotation_mode = "QUATERNION"
        obj.rotation_quaternion = Vector(direction).normalized().to_track_quat("-Z", "Y")
    bpy.context.scene.collection.objects.link(obj)
    info = dict(name=name, type=kind, power=power, location=Vector(location),
                direction=Vector(direction).normalized() if direction is not None else Vector((0, 0, -1)))
    if kind == "SPOT":
        outer = spot_size / 2
        cos_o = math.cos(outer)
        info.update(outer=outer, inner_gltf=outer - outer * spot_blend,
                    inner_cycles=math.acos(cos_o + (1 - cos_o) * spot_blend), blend=spot_blend)
    s.lights.append(info)
    return obj


def box(cx, cy, cz, sx, sy, sz, bottom=True):
    """Vertices and quads of an axis-aligned box (outward normals)."""
    x0, x1 = cx - sx / 2, cx + sx / 2
    y0, y1 = cy - sy / 2, cy + sy / 2
    z0, z1 = cz - sz / 2, cz + sz / 2
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    f = [(4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    if bottom:
        f.append((0, 3, 2, 1))
    return v, f


def merge(parts):
    verts, faces = [], []
    for v, f in parts:
        base = len(verts)
        verts.extend(v)
        faces.extend(tuple(base + i for i in q) for q in f)
    return verts, faces


CHAIR_LIFT = 0.01  # chairs stand 1 cm above the floor: no face touches the bake target


def chair_mesh():
    """A chair in its own frame (seat centred on the origin, back at -y):
    a seat, four legs and a back, joined into one mesh."""
    parts = [box(0, 0, 0.45, 0.45, 0.45, 0.05)]
    for sx in (-1, 1):
        for sy in (-1, 1):
            parts.append(box(sx * 0.19, sy * 0.19, 0.2125, 0.04, 0.04, 0.425))
    parts.append(box(0, -0.2, 0.725, 0.45, 0.05, 0.5, bottom=False))
    verts, faces = merge(parts)
    verts = [(x, y, z + CHAIR_LIFT) for (x, y, z) in verts]
    mesh = bpy.data.meshes.new("Chair")
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(lambert("ChairWood", CHAIR_WOOD))
    mesh.validate()
    mesh.update()
    return mesh


def add_chairs(s, placements):
    """Linked duplicates: one mesh datablock, one object per placement
    (x, y, rotation about z in degrees)."""
    mesh = chair_mesh()
    objs = []
    for k, (x, y, deg) in enumerate(placements):
        o = mesh_object("Chair.%s" % "ABC"[k], None, None, None, mesh=mesh)
        o.location = (x, y, 0)
        o.rotation_euler = (0, 0, math.radians(deg))
        objs.append(o)
    return objs


def add_alpha_plane(s, name, corners, material, mask, cells):
    """A cut-out quad; corners as in quad(). mask[j][i] is the alpha of
    cell (i along u, j along v) of a cells x cells grid."""
    obj = quad(name, *corners, material)
    p0, p1, _, p3 = [Vector(c) for c in corners]
    s.alpha_planes[name] = (p0, p1 - p0, p3 - p0, mask, cells)
    return obj


# ---------------------------------------------------------------------------
# The scenes


def scene_point():
    """A closed 4 x 4 x 2.5 m room, a 200 W point lamp, world black."""
    s = reset("point")
    set_world(s, None)
    build_room(s, 4, 4, 2.5)
    add_light(s, "Lamp", "POINT", 200.0, (0.125, -0.375, 1.5))
    return s


def scene_spot():
    """The closed room, a 400 W spot (60 degree cone, blend 0.25) aimed 20 degrees off vertical towards +x, world black."""
    s = reset("spot")
    set_world(s, None)
    build_room(s, 4, 4, 2.5)
    # Shines down and towards +x, 20 degrees off vertical.
    d = (math.sin(math.radians(20)), 0.0, -math.cos(math.radians(20)))
    add_light(s, "Spot", "SPOT", 400.0, (-0.5, 0.25, 2.2), direction=d,
              spot_size=math.radians(60), spot_blend=0.25)
    return s


# The window of the sun and room scenes, in the -x wall: y in [-1, 1], z in
# [0.5, 1.5]. A sun shining along +x and down at atan(1/2) (26.6 degrees
# elevation) puts the window's light on x in [-X + 1, -X + 3], y in [-1, 1]
# of the floor (a 2 m x 2 m patch): edges on block boundaries (multiples of
# 0.25 m from -X), so no block straddles the shadow's edge.
WINDOW = ((-1.0, 0.5), (1.0, 1.5))
SUN_DIR = (2.0, 0.0, -1.0)


def scene_sun():
    """The room with a 2 x 1 m window in the -x wall, a 5 W/m^2 sun at 26.6 degrees elevation shining through it, world black."""
    s = reset("sun")
    set_world(s, None)
    build_room(s, 4, 4, 2.5, window=WINDOW)
    add_light(s, "Sun", "SUN", 5.0, (-3.0, 0.0, 3.0), direction=SUN_DIR)
    return s


def scene_sky():
    """The room with a 2 x 1.5 m window in the -x wall, world a constant colour (0.6, 0.7, 0.9), no lamps."""
    s = reset("sky")
    set_world(s, SKY)
    build_room(s, 4, 4, 2.5, window=((-1.0, 0.5), (1.0, 2.0)))
    return s


def scene_texture():
    """The closed room, the floor's colour a checker texture (no factor), a 150 W point lamp under a shade plate; the ceiling sees only bounced light."""
    s = reset("texture")
    set_world(s, None)
    img = load_png(s, "FloorChecker", floor_texture_rows())
    floor_mat = lambert("FloorChecker", None, image=img)
    build_room(s, 4, 4, 2.5, floor_material=floor_mat, ceiling_target=True)
    # The lamp sits low under a shade plate, so the ceiling sees no lamp:
    # what reaches it was bounced, mostly off the textured floor.
    add_light(s, "Lamp", "POINT", 150.0, (0.0, 0.0, 0.8))
    shade = lambert("Shade", (0.6, 0.6, 0.6))
    v, f = box(0.0, 0.0, 1.0, 0.8, 0.8, 0.02)
    mesh_object("Shade", v, f, [shade])
    return s


def scene_cutout():
    """The room with a 3 x 3 m skylight filled by a leaf-masked plane (alphaMode MASK, alphaCutoff 0.3), a 4 W/m^2 sun straight down, world black."""
    s = reset("cutout")
    set_world(s, None)
    # A 3 m x 3 m skylight, the sun straight down through it and through a
    # leaf-masked plane that fills it (alphaCutoff 0.3, written out).
    # Each of the 12 x 12 mask cells shades exactly one 0.25 m floor block.
    build_room(s, 4, 4, 2.5, skylight=((-1.5, -1.5), (1.5, 1.5)))
    mask = leaf_cell_mask()
    img = load_png(s, "Leaf", leaf_texture_rows(mask))
    mat = lambert("Leaf", None, image=img, alpha_image=True, alpha_cutoff=0.3)
    z = 2.3
    corners = [(-1.5, -1.5, z), (1.5, -1.5, z), (1.5, 1.5, z), (-1.5, 1.5, z)]
    add_alpha_plane(s, "Leaf", corners, mat, mask, LEAF_CELLS)
    add_light(s, "Sun", "SUN", 4.0, (0.0, 0.0, 4.0), direction=(0.0, 0.0, -1.0))
    return s


def scene_instances():
    """The closed room, one chair mesh used by three objects (linked duplicates), a 250 W point lamp, world black."""
    s = reset("instances")
    set_world(s, None)
    build_room(s, 4, 4, 2.5)
    add_chairs(s, [(-1.0, 0.8, 0.0), (1.1, 0.5, 90.0), (0.2, -1.2, 200.0)])
    add_light(s, "Lamp", "POINT", 250.0, (0.1, 0.1, 2.0))
    return s


def scene_room():
    """A 6 x 4 x 2.6 m room: checker floor, a leaf-masked plant, three chair instances, a 120 W point lamp, a 300 W spot, a 5 W/m^2 sun and a constant sky (0.6, 0.7, 0.9) through a window."""
    s = reset("room")
    set_world(s, SKY)
    img = load_png(s, "FloorChecker", floor_texture_rows())
    floor_mat = lambert("FloorChecker", None, image=img)
    build_room(s, 6, 4, 2.6, window=WINDOW, floor_material=floor_mat)
    add_chairs(s, [(0.6, 1.1, 10.0), (1.8, 0.2, 80.0), (0.9, -1.2, 190.0)])
    # A plant: a pot and two crossed leaf quads.
    pot = lambert("Pot", (0.55, 0.3, 0.2))
    v, f = box(2.3, -1.3, 0.16, 0.3, 0.3, 0.3)
    mesh_object("Pot", v, f, [pot])
    leaves = load_png(s, "PlantLeaves", plant_texture_rows())
    leaf_mat = lambert("PlantLeaves", None, image=leaves, alpha_image=True)
    cx, cy, z0, z1, hw = 2.3, -1.3, 0.32, 1.22, 0.45
    plant_mask = None
    for name, (dx, dy) in (("Plant.A", (hw, 0.0)), ("Plant.B", (0.0, hw))):
        corners = [(cx - dx, cy - dy, z0), (cx + dx, cy + dy, z0), (cx + dx, cy + dy, z1), (cx - dx, cy - dy, z1)]
        if plant_mask is None:
            rows = plant_texture_rows()
            n = len(rows)
            plant_mask = [[1 if rows[n - 1 - j][i][3] else 0 for i in range(n)] for j in range(n)]
        add_alpha_plane(s, name, corners, leaf_mat, plant_mask, len(plant_mask))
    add_light(s, "Lamp", "POINT", 120.0, (-0.4, 0.3, 2.1))
    add_light(s, "Spot", "SPOT", 300.0, (2.6, 1.6, 2.4), direction=(-0.3, -0.45, -1.0),
              spot_size=math.radians(50), spot_blend=0.2)
    add_light(s, "Sun", "SUN", 5.0, (-4.0, 0.0, 3.0), direction=SUN_DIR)
    return s


SCENES = {"point": scene_point, "spot": scene_spot, "sun": scene_sun, "sky": scene_sky,
          "texture": scene_texture, "cutout": scene_cutout, "instances": scene_instances,
          "room": scene_room}


# ---------------------------------------------------------------------------
# Export and bake


def export_glb(path):
    tmp = path + ".tmp.glb"
    bpy.ops.export_scene.gltf(filepath=tmp, export_format="GLB", export_lights=True)
    os.replace(tmp, path)


def target_size(t):
    w = int(round(t["eu"].length * t.get("texels_per_metre", TEXELS_PER_METRE)))
    h = int(round(t["ev"].length * t.get("texels_per_metre", TEXELS_PER_METRE)))
    return w, h


def bake(t, seed, samples, passes):
    """Bake E/pi of the target into a float image; returns (h, w, 3), row 0
    at v = 0."""
    obj = t["obj"]
    w, h = target_size(t)
    img = bpy.data.images.new("bake_%s_%d" % (obj.name, seed), w, h, alpha=False, float_buffer=True)
    mat = obj.material_slots[0].material
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
    bpy.ops.object.bake(type="DIFFUSE", pass_filter=passes, margin=0, use_clear=True)
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    mat.node_tree.nodes.remove(node)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[:, :, :3].astype(np.float64)


def blocks(a, block):
    h, w = a.shape[:2]
    return a.reshape(h // block, block, w // block, block, -1).mean(axis=(1, 3))


def texel_positions(t):
    """Blender positions of the texel centres, (h, w, 3)."""
    w, h = target_size(t)
    u = (np.arange(w) + 0.5) / w
    v = (np.arange(h) + 0.5) / h
    o, eu, ev = (np.array(t[k][:]) for k in ("origin", "eu", "ev"))
    return o + u[None, :, None] * eu + v[:, None, None] * ev


def alpha_at(s, obj_name, p):
    o, eu, ev, mask, cells = s.alpha_planes[obj_name]
    d = Vector(p) - o
    u = d.dot(eu) / eu.length_squared
    v = d.dot(ev) / ev.length_squared
    i = min(max(int(u * cells), 0), cells - 1)
    j = min(max(int(v * cells), 0), cells - 1)
    return mask[j][i]


def visible(s, depsgraph, p, to_light, dist):
    """Whether the light is visible from p along unit to_light within dist,
    looking through cut-out planes where their alpha is 0."""
    sc = bpy.context.scene
    origin = Vector(p)
    left = dist
    for _ in range(64):
        hit, loc, _n, _i, obj, _m = sc.ray_cast(depsgraph, origin, to_light, distance=left)
        if not hit:
            return True
        if obj.name in s.alpha_planes and alpha_at(s, obj.name, loc) == 0:
            step = (loc - origin).length + 1e-5
            origin = origin + to_light * step
            left -= step
            if left <= 0:
                return True
            continue
        return False
    return False


def smoothstep(x):
    x = min(max(x, 0.0), 1.0)
    return x * x * (3 - 2 * x)


def direct_closed_form(s, t):
    """Per texel, E/pi from each delta light with visibility by ray casts
    (the closed form P/(4 pi) cos/d^2, S cos, Cycles' spot smoothstep), and
    per light per texel whether it lies in a spot's blend zone (between the
    smaller of the glTF and Cycles inner angles and the outer angle, padded
    by half a degree)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    pos = texel_positions(t)
    h, w = pos.shape[:2]
    n = t["normal"]
    offset = n * 1e-4
    out = []
    for L in s.lights:
        e = np.zeros((h, w))
        vis = np.zeros((h, w), dtype=bool)
        zone = np.zeros((h, w), dtype=bool)
        for r in range(h):
            for c in range(w):
                p = Vector(pos[r, c]) + offset
                if L["type"] == "SUN":
                    to_light = -L["direction"]
                    dist = 1e4
                    strength = L["power"]
                else:
                    d = L["location"] - p
                    dist = d.length
                    to_light = d / dist
                    strength = L["power"] / (4 * math.pi) / (dist * dist)
                    if L["type"] == "SPOT":
                        cos_a = (-to_light).dot(L["direction"])
                        ang = math.acos(max(-1.0, min(1.0, cos_a)))
                        lo = min(L["inner_gltf"], L["inner_cycles"]) - math.radians(0.5)
                        zone[r, c] = lo <= ang <= L["outer"] + math.radians(0.5)
                        cos_o = math.cos(L["outer"])
                        strength *= smoothstep((cos_a - cos_o) / ((1 - cos_o) * L["blend"]))
                cos_n = to_light.dot(n)
                if cos_n <= 0 or strength <= 0:
                    continue
                vis[r, c] = visible(s, depsgraph, p, to_light, dist)
                e[r, c] = strength * cos_n / math.pi if vis[r, c] else 0.0
        out.append(dict(light=L["name"], e=e, vis=vis, zone=zone))
    return out


def noise_stats(a, b):
    """Noise of the mean of two independent bakes a and b: per point the
    standard error estimate |a - b| / 2, relative to (a + b) / 2 (points
    darker than a millionth of the brightest left out)."""
    mean = (a + b) / 2
    err = np.abs(a - b) / 2
    top = float(mean.max())
    if top <= 0:
        return dict(rms_relative=None, max_relative=None, rms_absolute=0.0)
    ok = mean > 1e-6 * top
    rel = err[ok] / mean[ok]
    return dict(rms_relative=rnd(np.sqrt(np.mean(rel ** 2)), 4), max_relative=rnd(rel.max(), 4),
                rms_absolute=rnd(np.sqrt(np.mean(err ** 2)), 4))


# ---------------------------------------------------------------------------
# Reading back the GLB


def glb_json(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<III", data, 0)
    assert magic == 0x46546C67 and version == 2 and length == len(data), path
    clen, ctype = struct.unpack_from("<II", data, 12)
    assert ctype == 0x4E4F534A, path
    return json.loads(data[20:20 + clen].decode("utf-8"))


def quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def node_world(doc):
    """World (rotation, translation) of every node of the default scene."""
    out = {}

    def walk(i, R, T):
        n = doc["nodes"][i]
        r = quat_matrix(n.get("rotation", [0, 0, 0, 1]))
        sc = np.diag(n.get("scale", [1, 1, 1]))
        t = np.array(n.get("translation", [0, 0, 0]), dtype=float)
        R2 = R @ r @ sc
        T2 = T + R @ t
        out[i] = (R2, T2)
        for c in n.get("children", []):
            walk(c, R2, T2)

    for i in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        walk(i, np.eye(3), np.zeros(3))
    return out


def summarize_glb(path):
    doc = glb_json(path)
    world = node_world(doc)
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    placed = []
    for i, n in enumerate(doc["nodes"]):
        li = n.get("extensions", {}).get("KHR_lights_punctual", {}).get("light")
        if li is None:
            continue
        R, T = world[i]
        placed.append(dict(node=n.get("name"), light=lights[li], rotation=n.get("rotation"),
                           position=T.tolist(), direction=(R @ np.array([0, 0, -1.0])).tolist()))
    uses = {}
    for n in doc["nodes"]:
        if "mesh" in n:
            uses.setdefault(doc["meshes"][n["mesh"]]["name"], []).append(n["name"])
    mats = []
    for m in doc.get("materials", []):
        pbr = m.get("pbrMetallicRoughness", {})
        mats.append(dict(name=m.get("name"), alphaMode=m.get("alphaMode", "OPAQUE"),
                         alphaCutoff=m.get("alphaCutoff"), doubleSided=m.get("doubleSided", False),
                         baseColorFactor=pbr.get("baseColorFactor"),
                         baseColorTexture=pbr.get("baseColorTexture"),
                         metallicFactor=pbr.get("metallicFactor"), roughnessFactor=pbr.get("roughnessFactor"),
                         extensions=m.get("extensions")))
    return dict(file=os.path.basename(path), bytes=os.path.getsize(path),
                generator=doc["asset"].get("generator"),
                extensionsUsed=doc.get("extensionsUsed", []),
                extensionsRequired=doc.get("extensionsRequired", []),
                lights=placed, mesh_nodes=uses, materials=mats,
                textures=doc.get("textures", []), samplers=doc.get("samplers", []),
                images=[dict(name=im.get("name"), mimeType=im.get("mimeType")) for im in doc.get("images", [])])


# ---------------------------------------------------------------------------
# Truth


def rnd(x, digits=6):
    return float("%.*g" % (digits, x)) + 0.0  # + 0.0: no negative zeros


def truth_for_target(s, t, samples):
    w, h = target_size(t)
    block = t.get("block", BLOCK)
    full = [bake(t, seed, samples, {"DIRECT", "INDIRECT"}) for seed in (1, 2)]
    dsamples = max(samples // 4, 16)
    direct = [bake(t, seed, dsamples, {"DIRECT"}) for seed in (1, 2)]
    fa, fb = (blocks(x, block) for x in full)
    da, db = (blocks(x, block) for x in direct)
    truth = (fa + fb) / 2
    truth_direct = (da + db) / 2
    closed = direct_closed_form(s, t)
    closed_sum = sum(blocks(c["e"][:, :, None], block)[:, :, 0] for c in closed) if closed else None
    nv, nu = truth.shape[:2]
    edge = np.zeros((nv, nu), dtype=bool)
    zone = np.zeros((nv, nu), dtype=bool)
    for c in closed:
        lit = blocks((c["e"] > 0).astype(float)[:, :, None], block)[:, :, 0]
        edge |= (lit > 0) & (lit < 1)
        zone |= blocks(c["zone"].astype(float)[:, :, None], block)[:, :, 0] > 0
    points = []
    o, eu, ev = t["origin"], t["eu"], t["ev"]
    for j in range(nv):
        for i in range(nu):
            if zone[j, i]:
                continue
            p = o + eu * ((i + 0.5) / nu) + ev * ((j + 0.5) / nv)
            pt = dict(position=[rnd(x) for x in to_gltf(p)],
                      e_over_pi=[rnd(x) for x in truth[j, i]],
                      e_over_pi_direct=[rnd(x) for x in truth_direct[j, i]])
            if edge[j, i]:
                pt["edge"] = True
            points.append(pt)
    notes = ["Each point is the mean of a block of %d x %d texels of a %d x %d bake (block centre as "
             "position), and the mean of two bakes with seeds 1 and 2 of %d samples each."
             % (block, block, w, h, samples),
             "e_over_pi_direct: light that reaches the point without a bounce (lamps, and the world "
             "seen directly), Cycles' DIRECT pass only, two bakes of %d samples." % dsamples]
    if edge.any():
        notes.append("Points with \"edge\": true straddle a lamp's shadow edge (some of their texel "
                     "centres see the lamp, others do not, by ray casts through the alpha mask): "
                     "their value is a block mean, not the value at the centre; %d of them."
                     % int(edge.sum()))
    if zone.any():
        notes.append("%d blocks are left out: some texel centre lies in a spot's blend zone, between "
                     "the smaller of the glTF and Cycles inner cone angles and the outer angle, "
                     "padded by 0.5 degrees (Cycles' blend curve differs from glTF's)." % int(zone.sum()))
    out = dict(object=t["obj"].name, normal=[rnd(x) for x in to_gltf(t["normal"])],
               grid=dict(first=[rnd(x) for x in to_gltf(o + eu * (0.5 / nu) + ev * (0.5 / nv))],
                         step_u=[rnd(x) for x in to_gltf(eu / nu)], step_v=[rnd(x) for x in to_gltf(ev / nv)],
                         count=[nu, nv]),
               bake_size=[w, h], block=block,
               noise=noise_stats(fa, fb), noise_direct=noise_stats(da, db),
               note=notes, points=points)
    diag = dict(truth=truth, direct=truth_direct, closed=closed_sum, edge=edge, zone=zone,
                full_texel_noise=noise_stats(*full))
    return out, diag


def light_records(s, summary):
    recs = []
    by_name = {p["node"]: p for p in summary["lights"]}
    for L in s.lights:
        p = by_name[L["name"]]
        rec = dict(name=L["name"], type=p["light"]["type"],
                   blender=("strength %g W/m^2" % L["power"]) if L["type"] == "SUN" else ("power %g W" % L["power"]),
                   gltf_intensity=p["light"]["intensity"],
                   position=[rnd(x) for x in to_gltf(L["location"])] if L["type"] != "SUN" else None,
                   direction=[rnd(x) for x in to_gltf(L["direction"])] if L["type"] != "POINT" else None)
        if L["type"] == "SPOT":
            rec["gltf_inner_cone_angle"] = p["light"]["spot"]["innerConeAngle"]
            rec["gltf_outer_cone_angle"] = p["light"]["spot"]["outerConeAngle"]
            rec["cycles_full_intensity_angle"] = rnd(L["inner_cycles"])
        recs.append(rec)
    return recs


def check_export(s, summary):
    """The exported file holds what the scene should: lights placed and
    aimed as in Blender, in glTF coordinates."""
    problems = []
    by_name = {p["node"]: p for p in summary["lights"]}
    for L in s.lights:
        p = by_name.get(L["name"])
        if p is None:
            problems.append("light %s missing" % L["name"])
            continue
        if L["type"] != "SUN" and np.abs(np.array(p["position"]) - to_gltf(L["location"])).max() > 1e-5:
            problems.append("light %s at %s" % (L["name"], p["position"]))
        if L["type"] != "POINT" and np.abs(np.array(p["direction"]) - to_gltf(L["direction"])).max() > 1e-5:
            problems.append("light %s aims %s" % (L["name"], p["direction"]))
        want = L["power"] * W_TO_LM * (1 if L["type"] == "SUN" else 1 / (4 * math.pi))
        if abs(p["light"]["intensity"] - want) > 1e-4 * want:
            problems.append("light %s intensity %s, want %s" % (L["name"], p["light"]["intensity"], want))
    if s.lights and "KHR_lights_punctual" not in summary["extensionsUsed"]:
        problems.append("KHR_lights_punctual not in extensionsUsed")
    if s.alpha_planes and not any(m["alphaMode"] == "MASK" for m in summary["materials"]):
        problems.append("no MASK material")
    return problems


# Samples of each of the two bakes, chosen so the truth's noise (the mean
# of the two) stays well under 1% (reported in each truth file).
SAMPLES = {"point": 1024, "spot": 2048, "sun": 3072, "sky": 2048, "texture": 3072,
           "cutout": 3072, "instances": 1024, "room": 1024}


def make(name, outdir, samples):
    t0 = time.time()
    s = SCENES[name]()
    glb = os.path.join(outdir, name + ".glb")
    export_glb(glb)
    summary = summarize_glb(glb)
    problems = check_export(s, summary)
    print("[%s] export %s: %d bytes, extensionsUsed %s, extensionsRequired %s"
          % (name, summary["file"], summary["bytes"], summary["extensionsUsed"], summary["extensionsRequired"]))
    print("[%s] lights %s" % (name, json.dumps(summary["lights"])))
    print("[%s] meshes used by nodes %s" % (name, json.dumps(summary["mesh_nodes"])))
    print("[%s] materials %s" % (name, json.dumps(summary["materials"])))
    print("[%s] textures %s samplers %s images %s"
          % (name, summary["textures"], summary["samplers"], summary["images"]))
    if problems:
        raise SystemExit("[%s] export problems: %s" % (name, "; ".join(problems)))
    targets = []
    for t in s.targets:
        rec, diag = truth_for_target(s, t, samples)
        targets.append(rec)
        report(name, t, rec, diag, s)
    doc = {"scene": name, "description": SCENES[name].__doc__, "blender": bpy.app.version_string, "gltf_exporter": exporter_version(),
           "samples": samples, "max_bounces": MAX_BOUNCES,
           "units": "E/pi, W m^-2 sr^-1, linear Rec.709",
           "coordinates": "glTF (y up, metres): a Blender point (x, y, z) is (x, z, -y)",
           "world": s.world, "lights": light_records(s, summary), "targets": targets}
    text = json.dumps(doc, indent=1) + "\n"
    write_atomic(os.path.join(outdir, name + ".truth.json"), text.encode("utf-8"))
    shutil.rmtree(s.scratch, ignore_errors=True)
    print("[%s] done in %.0f s" % (name, time.time() - t0))
    return summary


def exporter_version():
    import addon_utils
    for mod in addon_utils.modules():
        if mod.__name__ == "io_scene_gltf2":
            return ".".join(str(x) for x in mod.bl_info["version"])
    return None


def report(name, t, rec, diag, s):
    print("[%s] %s: %d points, noise of the truth rms %.4f%% max %.3f%% (per texel of one bake rms %.2f%%), "
          "direct noise rms %s"
          % (name, rec["object"], len(rec["points"]), 100 * rec["noise"]["rms_relative"],
             100 * rec["noise"]["max_relative"], 100 * diag["full_texel_noise"]["rms_relative"] * math.sqrt(2),
             rec["noise_direct"]["rms_relative"]))
    closed = diag["closed"]
    if closed is None:
        return
    ok = (~diag["edge"]) & (~diag["zone"]) & (closed > 1e-3 * closed.max())
    if ok.any():
        ratio = diag["direct"][ok].mean(axis=-1) / closed[ok]
        print("[%s] %s: Cycles' direct over the closed form (lamps, ray-cast visibility), %d blocks: "
              "min %.4f median %.4f max %.4f%s" % (name, rec["object"], int(ok.sum()), ratio.min(),
                                                    np.median(ratio), ratio.max(),
                                                    " (Cycles' direct holds the world seen through the "
                                                    "window too)" if s.world is not None else ""))
    if name == "point" and t["normal"].z > 0:
        L = s.lights[0]
        nv, nu = closed.shape
        o, eu, ev = t["origin"], t["eu"], t["ev"]
        rows = []
        for j in range(nv):
            for i in range(nu):
                p = o + eu * ((i + 0.5) / nu) + ev * ((j + 0.5) / nv)
                d = (p - L["location"]).length
                rows.append((d, j, i, p))
        rows.sort(key=lambda r: r[0])
        for d, j, i, p in rows[:4]:
            tr = diag["truth"][j, i].mean()
            cf = closed[j, i]
            pc = L["location"] - p
            centre = L["power"] / (4 * math.pi) * (pc.z / pc.length) / pc.length_squared / math.pi
            print("[point] floor block at glTF %s, %.3f m from the lamp: truth E/pi %.5f; closed form "
                  "P/(4 pi) cos/d^2/pi at the centre %.5f, over the block %.5f; truth/direct %.4f "
                  "(the rest is interreflection)" % ([round(x, 4) for x in to_gltf(p)], d, tr, centre, cf, tr / cf))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("--only", default=None, help="comma-separated scene names")
    ap.add_argument("--samples", type=int, default=None, help="samples of each bake (default: per scene)")
    ap.add_argument("--example", default=None, help="also copy room.glb here")
    args = ap.parse_args(argv)
    names = list(SCENES) if args.only is None else args.only.split(",")
    for n in names:
        if n not in SCENES:
            raise SystemExit("unknown scene %r (scenes: %s)" % (n, ", ".join(SCENES)))
    os.makedirs(args.outdir, exist_ok=True)
    t0 = time.time()
    summaries = {}
    for n in names:
        summaries[n] = make(n, args.outdir, args.samples or SAMPLES[n])
    if args.example and "room" in names:
        tmp = args.example + ".tmp"
        shutil.copyfile(os.path.join(args.outdir, "room.glb"), tmp)
        os.replace(tmp, args.example)
    print("all done in %.0f s (Blender %s)" % (time.time() - t0, bpy.app.version_string))


if __name__ == "__main__":
    main(sys.argv[1:])
