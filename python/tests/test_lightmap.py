"""shlight.bake_lightmap against the CLI and a closed form: a floor with a
second UV set under a point lamp holds E = I cos / d^2 at its texels (in
three.js's units E and Bevy's E / pi), the same layers as `shlight
lightmap --exr`, byte for byte; a scene without TEXCOORD_1 raises the CLI's
message."""

import json
import math
import struct

import numpy as np
import pytest

import shlight

from conftest import cli_error, run_cli

LAMP = (0.3, 1.5, -0.2)


def floor_glb(path, uv1=True):
    """A 2 m floor (y = 0, facing up), both UV sets (x / 2 + 1/2, z / 2 +
    1/2) (the second left out with uv1=False), and a white point lamp of
    683 x 6 cd (6 W/sr in Blender's units) at LAMP."""
    corners = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)]
    binary = b"".join(struct.pack("<3f", *c) for c in corners)
    binary += b"".join(struct.pack("<3f", 0, 1, 0) for _ in corners)
    binary += b"".join(struct.pack("<2f", c[0] / 2 + 0.5, c[2] / 2 + 0.5) for c in corners)
    binary += struct.pack("<6H", 0, 3, 2, 0, 2, 1)
    binary += b"\0" * (-len(binary) % 4)
    attributes = {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}
    if uv1:
        attributes["TEXCOORD_1"] = 2
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "intensity": 683.0 * 6.0, "color": [1, 1, 1]}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0, "name": "Floor"},
                  {"translation": list(LAMP), "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                "metallicFactor": 0}}],
        "meshes": [{"name": "Floor", "primitives": [
            {"attributes": attributes, "indices": 3, "material": 0}]}],
        "buffers": [{"byteLength": len(binary)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1, 0, -1], "max": [1, 0, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks)
    return path


def black_sky(path):
    path.write_text(json.dumps({
        "format": "shlight-sh", "format_version": 1, "lmax": 2, "frame": "y-up",
        "mirror": False, "quantity": "radiance", "coefficients": [[0.0, 0.0, 0.0]] * 9,
        "provenance": {}}))
    return path


def test_a_floor_under_a_lamp_bakes_to_the_closed_form_and_the_clis_layers(cli, tmp_path):
    scene = floor_glb(tmp_path / "floor.glb")
    sky = black_sky(tmp_path / "black.json")
    flags = ["--size", "64", "--samples", "16", "--surface-samples", "16"]
    code, _, err = run_cli(cli, "lightmap", scene, "--env", sky, "--for", "bevy", *flags,
                           "--exr", tmp_path / "cli")
    assert code == 0, err
    lm = shlight.bake_lightmap(scene, sky, engine="bevy", size=64, samples=16,
                               surface_samples=16, exr=tmp_path / "py")
    assert (tmp_path / "py.irradiance.exr").read_bytes() == \
        (tmp_path / "cli.irradiance.exr").read_bytes()
    assert lm.side == 64 and lm.layer_names == ["irradiance"]
    layers = lm.layers
    assert layers.shape == (1, 64, 64, 4) and layers.dtype == np.float32
    (region,) = lm.regions
    assert region["node"] == 0 and region["rect"] == (2, 2, 60)
    # Texel (x, y) of the region is centred at floor point
    # ((x + 1/2) / 60 * 2 - 1, 0, (y + 1/2) / 60 * 2 - 1).
    t = (np.arange(60) + 0.5) / 60 * 2 - 1
    x, z = np.meshgrid(t, t)
    d = np.stack([LAMP[0] - x, np.full_like(x, LAMP[1]), LAMP[2] - z], axis=-1)
    d2 = (d ** 2).sum(axis=-1)
    e = 6.0 * d[..., 1] / d2 ** 1.5
    got = lm.irradiance[2:62, 2:62]
    assert np.abs(got[..., 0] / e - 1).max() < 0.015
    # Bevy's texels are E / pi.
    assert np.allclose(layers[0, 2:62, 2:62, 0], got[..., 0] / math.pi, rtol=1e-5)


def test_a_scene_without_a_second_uv_set_raises_the_clis_message(cli, tmp_path):
    scene = floor_glb(tmp_path / "floor.glb", uv1=False)
    sky = black_sky(tmp_path / "black.json")
    code, _, err = run_cli(cli, "lightmap", scene, "--env", sky, "--size", "32")
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.bake_lightmap(scene, sky, size=32)
    assert str(e.value) == cli_error(err)
    assert "has no UV set 1 (TEXCOORD_1)" in str(e.value)
    with pytest.raises(shlight.ShlightError, match='basis="monosh" with engine="godot"'):
        shlight.bake_lightmap(scene, sky, basis="monosh", engine="godot")


def test_denoise_is_the_clis_flag(cli, tmp_path):
    """denoise=0 bakes what `--denoise 0` bakes, byte for byte, and not what
    the default filter (radius 2) bakes."""
    scene = floor_glb(tmp_path / "floor.glb")
    sky = black_sky(tmp_path / "black.json")
    flags = ["--size", "32", "--samples", "16", "--surface-samples", "16"]
    code, _, err = run_cli(cli, "lightmap", scene, "--env", sky, *flags, "--denoise", "0",
                           "--exr", tmp_path / "cli")
    assert code == 0, err
    for name, radius in (("raw", 0), ("filtered", 2)):
        shlight.bake_lightmap(scene, sky, size=32, samples=16, surface_samples=16,
                              denoise=radius, exr=tmp_path / name)
    cli_bytes = (tmp_path / "cli.irradiance.exr").read_bytes()
    assert (tmp_path / "raw.irradiance.exr").read_bytes() == cli_bytes
    assert (tmp_path / "filtered.irradiance.exr").read_bytes() != cli_bytes


def test_sample_reads_the_written_scene_at_points_as_the_cli_does(cli, tmp_path):
    """shlight.sample on the GLB bake_lightmap wrote: the lamp's I cos / d^2
    at points of the floor (within the 1.5% a texel's half-width allows),
    and the CLI's answer for the same file and points."""
    scene = floor_glb(tmp_path / "floor.glb")
    sky = black_sky(tmp_path / "black.json")
    out = tmp_path / "lit.glb"
    shlight.bake_lightmap(scene, sky, output=out, size=64, samples=16, surface_samples=16)
    pts = [(x, 0.0, z) for x in (-0.7, -0.2, 0.3, 0.8) for z in (-0.6, 0.1, 0.7)]
    points = tmp_path / "points.json"
    points.write_text(json.dumps({"points": pts, "normals": [(0, 1, 0)] * len(pts)}))
    shlight.sample(out, tmp_path / "py.json", points=points)
    code, _, err = run_cli(cli, "sample", out, "--points", points, "-o", tmp_path / "cli.json")
    assert code == 0, err
    py = json.loads((tmp_path / "py.json").read_text())
    assert py["irradiance"] == json.loads((tmp_path / "cli.json").read_text())["irradiance"]
    for (x, _, z), e in zip(pts, py["irradiance"]):
        d = np.array([LAMP[0] - x, LAMP[1], LAMP[2] - z])
        want = 6.0 * d[1] / np.dot(d, d) ** 1.5
        assert abs(e[0] / want - 1) < 0.015, (x, z, e, want)
