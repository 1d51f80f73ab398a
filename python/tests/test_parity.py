"""What the command line writes, Python writes: every file of every
command reachable from Python is compared byte for byte with the CLI's
(docs/python.md, "Every command from Python", names the test of each)."""

import warnings

import pytest

import shlight

from conftest import ENVMAPS, ROOT, cli_error, run_cli

PARK = ENVMAPS / "park.exr"
SKY = ENVMAPS / "sky.exr"
BOX = ROOT / "meshes" / "cornell_box.obj"
POINTS = ROOT / "meshes" / "cornell_box_points.json"


def quietly(f, *args, **kwargs):
    """A call without the bundled maps' negative-texel warnings."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return f(*args, **kwargs)


@pytest.mark.parametrize(
    "name, flags, options",
    [
        ("light.gltf", ["--format", "gltf", "--specular-size", "16", "--specular-samples", "16"],
         {"format": "gltf", "specular_size": 16, "specular_samples": 16}),
        ("light.glb", ["--format", "gltf", "--specular-size", "16", "--specular-samples", "16"],
         {"format": "gltf", "specular_size": 16, "specular_samples": 16}),
        ("probe.json", ["--format", "threejs"], {"format": "threejs"}),
        ("sh.hlsl", ["--format", "hlsl", "--lmax", "3"], {"format": "hlsl", "lmax": 3}),
        ("park.json", ["--lmax", "4", "--window", "auto"], {"lmax": 4, "window": "auto"}),
    ],
)
def test_project_writes_the_clis_files(cli, tmp_path, name, flags, options):
    code, _, err = run_cli(cli, "project", SKY, *flags, "-o", tmp_path / f"cli-{name}", "-q")
    assert code == 0, err
    sh = quietly(shlight.project, str(SKY), output=tmp_path / f"py-{name}", **options)
    assert (tmp_path / f"py-{name}").read_bytes() == (tmp_path / f"cli-{name}").read_bytes()
    # The SH returned is the file written.
    assert sh.lmax == options.get("lmax", 2)


def test_project_previews_and_batches_are_the_clis(cli, tmp_path):
    maps = [str(PARK), str(SKY)]
    code, _, err = run_cli(
        cli, "project", *maps, "-o", tmp_path / "cli", "--preview", tmp_path / "cli-previews",
        "--preview-size", "32x16", "--format", "txt", "-q",
    )
    assert code == 0, err
    many = quietly(
        shlight.project_many, maps, output=tmp_path / "py", preview=tmp_path / "py-previews",
        preview_size=(32, 16), format="txt",
    )
    assert [s.lmax for s in many] == [2, 2]
    for name in ["park", "sky"]:
        assert (tmp_path / "py" / f"{name}.txt").read_bytes() == (tmp_path / "cli" / f"{name}.txt").read_bytes()
        assert (tmp_path / "py-previews" / f"{name}.png").read_bytes() == (
            tmp_path / "cli-previews" / f"{name}.png"
        ).read_bytes()


def test_project_refuses_outputs_of_arrays_and_formats_without_output(tmp_path):
    import numpy as np

    with pytest.raises(shlight.ShlightError, match="a map file"):
        shlight.project(np.ones((8, 16, 3), np.float32), output=tmp_path / "x.json")
    with pytest.raises(shlight.ShlightError, match="format"):
        shlight.project(str(SKY), format="bogus", output=tmp_path / "x.json")
    # Settings are named as Python spells them.
    with pytest.raises(shlight.ShlightError, match=r"^preview_size: "):
        shlight.project(str(SKY), preview=tmp_path / "p.png", preview_size=(10, 10))


@pytest.mark.parametrize("name", ["cube.ktx", "cube.ktx2"])
def test_prefilter_writes_the_clis_ktx_files(cli, tmp_path, name):
    code, _, err = run_cli(cli, "prefilter", PARK, "-o", tmp_path / f"cli-{name}", "--size", "16", "--samples", "16", "-q")
    assert code == 0, err
    files = quietly(shlight.prefilter, str(PARK), tmp_path / f"py-{name}", size=16, samples=16)
    assert files == [str(tmp_path / f"py-{name}")]
    assert (tmp_path / f"py-{name}").read_bytes() == (tmp_path / f"cli-{name}").read_bytes()


def test_prefilter_and_dfg_refusals_name_python_settings(tmp_path):
    with pytest.raises(shlight.ShlightError, match=r"^size: .*power of two"):
        shlight.prefilter(str(PARK), tmp_path / "x", size=48)
    with pytest.raises(shlight.ShlightError, match=r"^size: .*from 1 to 4096"):
        shlight.dfg(tmp_path / "d.exr", size=5000)
    with pytest.raises(shlight.ShlightError, match="output names a directory"):
        shlight.prefilter(str(PARK), tmp_path / "x.exr")


def test_render_draws_the_clis_lobe(cli, tmp_path):
    coeffs = tmp_path / "park.json"
    code, _, err = run_cli(cli, "project", PARK, "--lmax", "3", "-o", coeffs, "-q")
    assert code == 0, err
    code, _, err = run_cli(cli, "render", coeffs, "-o", tmp_path / "lobe.exr", "--layout", "lobe", "--size", "32x24", "--view", "1,2,3")
    assert code == 0, err
    want = shlight.read_image(tmp_path / "lobe.exr")
    got = shlight.render(shlight.load(coeffs), (32, 24), layout="lobe", view=(1, 2, 3))
    # The EXR holds the same float32 values the array does.
    assert (got == want).all()
    with pytest.raises(shlight.ShlightError, match=r'^view is where layout="lobe" is seen from'):
        shlight.render(shlight.load(coeffs), layout="equirect", view=(1, 0, 0))


@pytest.fixture(scope="module")
def baked(cli, tmp_path_factory):
    """A small volume and a diffuse PRT file, baked by the CLI."""
    d = tmp_path_factory.mktemp("baked")
    light = d / "park.json"
    assert run_cli(cli, "project", PARK, "--lmax", "4", "-o", light, "-q")[0] == 0
    volume = d / "box.shvol"
    code, _, err = run_cli(
        cli, "volume", BOX, "--env", light, "--resolution", "3x2x3", "--samples", "128",
        "--surface-samples", "64", "-o", volume, "-q",
    )
    assert code == 0, err
    transfer = d / "bunny.shprt"
    code, _, err = run_cli(cli, "prt", ROOT / "meshes" / "bunny.obj", "--samples", "64", "--lmax", "3", "-o", transfer, "-q")
    assert code == 0, err
    return {"light": light, "volume": volume, "transfer": transfer}


@pytest.mark.parametrize(
    "kind, flags, options",
    [
        ("volume", ["--points", POINTS], {"points": POINTS}),
        ("volume", ["--points", POINTS, "--lookup", "threejs", "--env", SKY],
         {"points": POINTS, "lookup": "threejs", "env": SKY}),
        ("transfer", ["--lmax", "2"], {"lmax": 2}),
    ],
)
def test_sample_writes_the_clis_answer(cli, tmp_path, baked, kind, flags, options):
    file = baked[kind]
    if kind == "transfer":
        flags = [*flags, "--light", baked["light"]]
        options = {**options, "light": baked["light"]}
    code, _, err = run_cli(cli, "sample", file, *flags, "-o", tmp_path / "cli.json", "-q")
    assert code == 0, err
    quietly(shlight.sample, file, tmp_path / "py.json", **options)
    assert (tmp_path / "py.json").read_bytes() == (tmp_path / "cli.json").read_bytes()


def test_sample_refusals_are_the_clis_in_python_spelling(cli, tmp_path, baked):
    code, _, err = run_cli(cli, "sample", baked["volume"], "-o", tmp_path / "x.json")
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.sample(baked["volume"], tmp_path / "x.json")
    assert "sampling a volume needs" in cli_error(err) and "sampling a volume needs" in str(e.value)
    assert "--points" in cli_error(err) and "--points" not in str(e.value)
    code, _, err = run_cli(cli, "sample", baked["transfer"], "--light", baked["light"], "--env", SKY, "-o", tmp_path / "x.json")
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.sample(baked["transfer"], tmp_path / "x.json", light=baked["light"], env=SKY)
    assert str(e.value) == cli_error(err).replace("--env", "env").replace("--light", "light")


def test_synth_writes_the_clis_map(cli, tmp_path):
    flags = ["cap", "--size", "64x32", "--half-angle", "25", "--direction", "1,1,0", "--value", "3", "--up", "z"]
    code, _, err = run_cli(cli, "synth", *flags, "-o", tmp_path / "cli.exr")
    assert code == 0, err
    image = shlight.synth(
        "cap", (64, 32), half_angle=25, direction=(1, 1, 0), value=3, up="z", output=tmp_path / "py.exr"
    )
    assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert (image == shlight.read_image(tmp_path / "cli.exr")).all()
    with pytest.raises(shlight.ShlightError, match=r"^half_angle=120: .*at most 90 degrees"):
        shlight.synth("directional", (16, 8), half_angle=120)


def test_convert_writes_the_clis_files(cli, tmp_path, baked):
    for name, flags, options in [
        ("unity.json", ["--format", "unity"], {"format": "unity"}),
        ("light.glsl", [], {}),
    ]:
        code, _, err = run_cli(cli, "convert", baked["light"], *flags, "-o", tmp_path / f"cli-{name}")
        assert code == 0, err
        shlight.convert(baked["light"], tmp_path / f"py-{name}", **options)
        assert (tmp_path / f"py-{name}").read_bytes() == (tmp_path / f"cli-{name}").read_bytes(), name
    code, out, err = run_cli(cli, "convert", baked["light"], "--format", "threejs")
    assert code == 0, err
    assert shlight.convert(baked["light"], format="threejs") == out
    # A volume as three.js's grid and as a WGSL snippet with its textures.
    code, _, err = run_cli(cli, "convert", baked["volume"], "--format", "threejs", "-o", tmp_path / "cli-grid.json")
    assert code == 0, err
    shlight.convert(baked["volume"], tmp_path / "py-grid.json", format="threejs")
    assert (tmp_path / "py-grid.json").read_bytes() == (tmp_path / "cli-grid.json").read_bytes()
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    code, _, err = run_cli(cli, "convert", baked["volume"], "-o", tmp_path / "cli" / "box.wgsl")
    assert code == 0, err
    written = shlight.convert(baked["volume"], tmp_path / "py" / "box.wgsl")
    assert len(written) >= 2
    for path in written:
        name = path.split("/")[-1]
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    with pytest.raises(shlight.ShlightError, match=r"writing to stdout needs format \(or give output\)"):
        shlight.convert(baked["light"])


def test_irradiance_writes_the_clis_files_and_errors(cli, tmp_path):
    code, out, err = run_cli(
        cli, "irradiance", SKY, "-o", tmp_path / "cli.exr", "--size", "32x16", "--encoding", "dominant+sh",
        "--error-map", tmp_path / "cli-map.png",
    )
    assert code == 0, err
    got = quietly(
        shlight.irradiance, SKY, (32, 16), encoding="dominant+sh", output=tmp_path / "py.exr",
        error_map=tmp_path / "py-map.png",
    )
    for cli_name, py_name in [
        ("cli.exr", "py.exr"), ("cli-dominant+sh.exr", "py-dominant+sh.exr"),
        ("cli-diff.exr", "py-diff.exr"), ("cli-map.png", "py-map.png"),
    ]:
        assert (tmp_path / py_name).read_bytes() == (tmp_path / cli_name).read_bytes(), py_name
    # The summary is the CLI's, and its percentages are the dict's.
    assert got["summary"] == out
    assert f"max {100 * got['max_peak_relative']:.3f}%" in out
    assert got["exact"].shape == got["estimate"].shape == (16, 32, 3)
    with pytest.raises(shlight.ShlightError, match=r"^error_map needs sh or encoding"):
        shlight.irradiance(SKY, error_map=tmp_path / "x.png")


def test_compare_and_accuracy_write_the_clis_files(cli, tmp_path):
    code, _, err = run_cli(cli, "compare", SKY, "--normals", "16x8", "-o", tmp_path / "cli")
    assert code == 0, err
    rows = quietly(shlight.compare, [SKY], (16, 8), output=tmp_path / "py")
    for name in ["compare.json", "compare-sky.svg"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert rows[0]["map"] == "sky"
    code, out, err = run_cli(cli, "accuracy", "--quick", "--json")
    assert code == 0, err
    import json

    assert shlight.accuracy(quick=True) == json.loads(out)


@pytest.mark.parametrize(
    "name, flags, options",
    [
        ("g.shprt", ["--mode", "glossy", "--brdf", "phong:16", "--bounces", "1"],
         {"mode": "glossy", "brdf": "phong:16", "bounces": 1}),
        ("ggx.shprt", ["--mode", "glossy", "--brdf", "ggx:0.3,0.04", "--compress", "cpca:4,3"],
         {"mode": "glossy", "brdf": "ggx:0.3,0.04", "compress": "cpca:4,3"}),
        ("t.glb", ["--mode", "interreflected", "--albedo", "0.8,0.6,0.4"],
         {"mode": "interreflected", "albedo": (0.8, 0.6, 0.4)}),
    ],
)
def test_bake_transfer_writes_the_clis_glossy_compressed_and_gltf_files(cli, tmp_path, name, flags, options):
    teapot = ROOT / "meshes" / "teapot.obj"
    common = ["--lmax", "2", "--samples", "64"]
    code, _, err = run_cli(cli, "prt", teapot, *common, *flags, "-o", tmp_path / f"cli-{name}", "-q")
    assert code == 0, err
    t = shlight.bake_transfer(teapot, lmax=2, samples=64, output=tmp_path / f"py-{name}", **options)
    assert (tmp_path / f"py-{name}").read_bytes() == (tmp_path / f"cli-{name}").read_bytes()
    if options.get("mode") == "glossy":
        assert t.mode == "glossy" and t.brdf == options["brdf"]


def test_bake_transfer_draws_the_clis_preview(cli, tmp_path, baked):
    bunny = ROOT / "meshes" / "bunny.obj"
    flags = ["--samples", "64", "--light", baked["light"], "--preview-size", "48x40"]
    code, _, err = run_cli(cli, "prt", bunny, *flags, "--preview", tmp_path / "cli.png", "-q")
    assert code == 0, err
    shlight.bake_transfer(bunny, samples=64, light=baked["light"], preview=tmp_path / "py.png", preview_size=(48, 40))
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    with pytest.raises(shlight.ShlightError, match=r"^compress compresses the matrices of mode=\"glossy\""):
        shlight.bake_transfer(bunny, compress="cpca:2,2")
    with pytest.raises(shlight.ShlightError, match=r"^light needs preview"):
        shlight.bake_transfer(bunny, light=baked["light"])


def test_bake_volume_writes_the_clis_grid_and_probe_picture(cli, tmp_path, baked):
    flags = ["--resolution", "3x2x3", "--samples", "128", "--surface-samples", "64"]
    code, _, err = run_cli(
        cli, "volume", BOX, "--env", baked["light"], *flags, "--format", "threejs", "--precision", "f32",
        "-o", tmp_path / "cli.json", "--preview", tmp_path / "cli.png", "--preview-ball", "12", "-q",
    )
    assert code == 0, err
    v = shlight.bake_volume(
        BOX, baked["light"], resolution=(3, 2, 3), samples=128, surface_samples=64, format="threejs",
        precision="f32", output=tmp_path / "py.json", preview=tmp_path / "py.png", preview_ball=12,
    )
    for name in ["json", "png"]:
        assert (tmp_path / f"py.{name}").read_bytes() == (tmp_path / f"cli.{name}").read_bytes(), name
    # The volume writes any form the CLI writes.
    v.write(tmp_path / "again.json", format="threejs", precision="f32")
    assert (tmp_path / "again.json").read_bytes() == (tmp_path / "cli.json").read_bytes()
    with pytest.raises(shlight.ShlightError, match=r'^precision="double": '):
        v.write(tmp_path / "x.json", format="threejs", precision="double")


def test_a_map_over_the_pixel_limit_names_the_keyword(cli, tmp_path):
    code, _, err = run_cli(cli, "project", PARK, "--max-pixels", "1000", "-o", tmp_path / "x.json")
    assert code != 0 and "raise the limit with --max-pixels" in cli_error(err)
    with pytest.raises(shlight.ShlightError) as e:
        shlight.project(str(PARK), max_pixels=1000)
    assert str(e.value) == cli_error(err).replace("--max-pixels", "max_pixels")
