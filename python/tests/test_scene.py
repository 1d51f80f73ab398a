"""shlight.load_scene and shlight.Scene against the CLI and the glTF file:
what a scene holds (counts, materials, lights as written); a loaded scene
and its path give `shlight prt`'s and `shlight volume`'s files byte for
byte; `sample(points=scene)` gives `shlight sample --points SCENE.glb`'s
values; and bad input raises the CLI's messages."""

import json
import struct

import pytest

import shlight

from conftest import ROOT, cli_error, run_cli

SCENES = ROOT / "tests" / "scenes"
POINT = SCENES / "point.glb"
INSTANCES = SCENES / "instances.glb"
CUTOUT = SCENES / "cutout.glb"


def glb_json(path):
    """The JSON chunk of a GLB file, read here by its layout (glTF 2.0,
    section 4.4): a 12-byte header, then the chunk's length and type."""
    data = path.read_bytes()
    length, kind = struct.unpack_from("<II", data, 12)
    assert kind == 0x4E4F534A
    return json.loads(data[20 : 20 + length])


def test_a_scene_shows_what_its_file_holds():
    doc = glb_json(INSTANCES)
    scene = shlight.load_scene(INSTANCES)
    # One instance per primitive of every node that has a mesh.
    nodes = [n for n in doc["nodes"] if "mesh" in n]
    want_instances = sum(len(doc["meshes"][n["mesh"]]["primitives"]) for n in nodes)
    assert scene.instance_count == want_instances
    assert scene.primitive_count == sum(len(m["primitives"]) for m in doc["meshes"])
    assert scene.instance_count > scene.primitive_count  # the chairs are shared
    assert len(scene.materials) == len(doc["materials"])
    for got, want in zip(scene.materials, doc["materials"]):
        assert got["name"] == want.get("name")
        pbr = want.get("pbrMetallicRoughness", {})
        assert got["base_color"] == pytest.approx(pbr.get("baseColorFactor", [1, 1, 1, 1]))
    lamp = doc["extensions"]["KHR_lights_punctual"]["lights"]
    assert [l["intensity"] for l in scene.lights] == pytest.approx([l["intensity"] for l in lamp])
    assert [l["kind"] for l in scene.lights] == [l["type"] for l in lamp]
    assert all(l["units"] == "cd" for l in scene.lights)
    assert "instances.glb" in repr(scene)
    cut = shlight.load_scene(CUTOUT)
    assert any(m["alpha_mode"] == "mask" and m["alpha_cutoff"] == pytest.approx(0.3)
               for m in cut.materials)
    assert [l["units"] for l in cut.lights] == ["lux"]


def test_a_loaded_scene_bakes_the_clis_prt_file(cli, tmp_path):
    flags = ["--samples", "64", "--lmax", "2", "--mode", "interreflected", "--bounces", "1"]
    out = tmp_path / "cli.shprt"
    code, _, err = run_cli(cli, "prt", POINT, *flags, "-o", out)
    assert code == 0, err
    options = {"samples": 64, "lmax": 2, "bounces": 1}
    scene = shlight.load_scene(POINT)
    by_object = shlight.bake_transfer(scene, "interreflected", **options)
    by_path = shlight.bake_transfer(str(POINT), "interreflected", **options,
                                    output=tmp_path / "py.shprt")
    assert (tmp_path / "py.shprt").read_bytes() == out.read_bytes()
    by_object.save(tmp_path / "object.shprt")
    assert (tmp_path / "object.shprt").read_bytes() == out.read_bytes()
    assert by_path.vertex_count == scene.vertex_count
    # as-written intensities: the static term 683 times the blender one.
    code, _, err = run_cli(cli, "prt", POINT, *flags, "--light-units", "as-written",
                           "-o", tmp_path / "raw.shprt")
    assert code == 0, err
    raw = shlight.bake_transfer(scene, "interreflected", **options, light_units="as-written")
    raw.save(tmp_path / "raw-py.shprt")
    assert (tmp_path / "raw-py.shprt").read_bytes() == (tmp_path / "raw.shprt").read_bytes()


def test_a_scene_refuses_an_albedo_and_a_mesh_light_units(cli, tmp_path):
    code, _, err = run_cli(cli, "prt", POINT, "--albedo", "0.5", "-o", tmp_path / "x.shprt")
    assert code != 0 and "a glTF scene's albedo is its materials'" in cli_error(err)
    with pytest.raises(shlight.ShlightError, match="albedo sets one albedo for every vertex"):
        shlight.bake_transfer(shlight.load_scene(POINT), albedo=0.5)
    bunny = ROOT / "meshes" / "bunny.obj"
    with pytest.raises(shlight.ShlightError, match="light_units reads a glTF scene's punctual"):
        shlight.bake_transfer(bunny, light_units="as-written")
    with pytest.raises(shlight.ShlightError, match="a scene is a glTF file"):
        shlight.load_scene(bunny)


def test_a_loaded_scene_bakes_the_clis_volume_and_is_sampled_at_its_vertices(cli, tmp_path):
    sky = tmp_path / "sky.json"
    rows = [[0.0, 0.0, 0.0]] * 9
    rows[0] = [1.0, 1.0, 1.0]
    sky.write_text(json.dumps({
        "format": "shlight-sh", "format_version": 1, "lmax": 2, "frame": "y-up",
        "mirror": False, "quantity": "radiance", "coefficients": rows, "provenance": {},
    }))
    flags = ["--resolution", "2x2x2", "--samples", "64", "--surface-samples", "32",
             "--bounces", "1", "--max-edge", "0.5"]
    out = tmp_path / "cli.shvol"
    code, _, err = run_cli(cli, "volume", POINT, "--env", sky, *flags, "-o", out)
    assert code == 0, err
    scene = shlight.load_scene(POINT)
    vol = shlight.bake_volume(scene, sky, resolution=(2, 2, 2), samples=64,
                              surface_samples=32, bounces=1, max_edge=0.5,
                              output=tmp_path / "py.shvol")
    assert (tmp_path / "py.shvol").read_bytes() == out.read_bytes()
    assert vol.lights["point"] == 1
    cli_json = tmp_path / "cli-vertices.json"
    code, _, err = run_cli(cli, "sample", out, "--points", POINT, "-o", cli_json)
    assert code == 0, err
    py_json = tmp_path / "py-vertices.json"
    shlight.sample(out, py_json, points=scene)
    by_path = tmp_path / "path-vertices.json"
    shlight.sample(out, by_path, points=POINT)
    want = json.loads(cli_json.read_text())
    assert len(want["irradiance"]) == scene.vertex_count
    assert json.loads(py_json.read_text())["irradiance"] == want["irradiance"]
    assert json.loads(by_path.read_text()) == want


def test_the_static_term_is_in_the_transfer_and_its_exit_radiance(tmp_path):
    t = shlight.bake_transfer(shlight.load_scene(POINT), samples=32, lmax=1)
    s = t.static_radiance
    assert s.shape == (t.vertex_count, 3) and s.max() > 0
    black = tmp_path / "black.json"
    black.write_text(json.dumps({
        "format": "shlight-sh", "format_version": 1, "lmax": 1, "frame": "y-up",
        "mirror": False, "quantity": "radiance", "coefficients": [[0.0] * 3] * 4,
        "provenance": {},
    }))
    assert t.exit_radiance(black) == pytest.approx(s.astype(float), rel=1e-6, abs=1e-9)
    bunny = shlight.bake_transfer(ROOT / "meshes" / "bunny.obj", samples=16, lmax=1)
    assert bunny.static_radiance is None
