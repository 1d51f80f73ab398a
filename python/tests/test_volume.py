"""shlight.bake_volume and shlight.Volume against the CLI: a bake writes
`shlight volume`'s file byte for byte, `Volume.irradiance` gives `shlight
sample`'s values for every lookup, `Volume.relight` gives `shlight sample
--env`'s, and bad inputs raise the CLI's messages."""

import json
import warnings

import numpy as np
import pytest

import shlight

from conftest import ENVMAPS, ROOT, cli_error, run_cli

BOX = ROOT / "meshes" / "cornell_box.obj"
PARK = ENVMAPS / "park.exr"
SKY = ENVMAPS / "sky.exr"
LOOKUPS = ["shlight", "trilinear", "bevy", "threejs"]

# A small bake: 32 probes, quick on two cores.
SMALL_FLAGS = ["--resolution", "4x2x4", "--samples", "256", "--surface-samples", "128"]
SMALL = {"resolution": (4, 2, 4), "samples": 256, "surface_samples": 128}

# Every option away from its default.
OTHER_FLAGS = [
    "--resolution", "3x3x2", "--samples", "128", "--surface-samples", "64",
    "--lmax", "3", "--bounces", "1", "--albedo", "0.5,0.6,0.7", "--seed", "4",
    "--invalid-backfaces", "0.3", "--no-relocate", "--no-visibility", "--static",
    "--bounds=-0.1,0,0:0.6,0.5,0.5",
]
OTHER = {
    "resolution": "3x3x2", "samples": 128, "surface_samples": 64, "lmax": 3, "bounces": 1,
    "albedo": (0.5, 0.6, 0.7), "seed": 4, "invalid_backfaces": 0.3, "relocate": False,
    "visibility": False, "static": True, "bounds": ((-0.1, 0.0, 0.0), (0.6, 0.5, 0.5)),
}

# What the JSON's f64 values and the Python ones may differ by (both are
# the same library call on the same float32 inputs: measured equal).
RTOL = 1e-9


def bake_quietly(*args, **kwargs):
    """bake_volume without the bundled maps' negative-texel warnings."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return shlight.bake_volume(*args, **kwargs)


@pytest.fixture(scope="module")
def baked(cli, tmp_path_factory):
    """The CLI's small bake of the Cornell box under park.exr, and one
    without distance maps (whose shlight lookup is trilinear)."""
    d = tmp_path_factory.mktemp("volume")
    files = {}
    for name, extra in [("full", []), ("plain", ["--no-visibility"])]:
        path = d / f"{name}.shvol"
        code, _, err = run_cli(cli, "volume", BOX, "--env", PARK, *SMALL_FLAGS, *extra, "-o", path)
        assert code == 0, err
        files[name] = path
    return files


def points_and_normals(volume, n, seed):
    """`n` points over the volume's box grown by a tenth (so some fall
    outside it) and random normals, float64."""
    rng = np.random.default_rng(seed)
    lo, hi = (np.array(b, np.float64) for b in volume.bounds)
    grow = 0.1 * (hi - lo)
    points = rng.uniform(lo - grow, hi + grow, (n, 3))
    normals = rng.normal(size=(n, 3))
    return points, normals


def cli_sample(cli, tmp_path, file, points, normals, *flags):
    """`shlight sample FILE --points ... FLAGS`: the irradiance, (N, 3)."""
    pts = tmp_path / "points.json"
    pts.write_text(json.dumps({"points": points.tolist(), "normals": normals.tolist()}))
    out = tmp_path / "samples.json"
    code, _, err = run_cli(cli, "sample", file, "--points", pts, *flags, "-o", out)
    assert code == 0, err
    return np.array(json.loads(out.read_text())["irradiance"], np.float64)


@pytest.mark.parametrize(
    "flags,options",
    [(SMALL_FLAGS, SMALL), (OTHER_FLAGS, OTHER)],
    ids=["defaults", "every option"],
)
@pytest.mark.parametrize("ext", ["shvol", "json", "ktx2"])
def test_bakes_equal_the_clis_files(cli, tmp_path, flags, options, ext):
    env = SKY if options is OTHER else PARK
    want = tmp_path / f"cli.{ext}"
    code, _, err = run_cli(cli, "volume", BOX, "--env", env, *flags, "-o", want)
    assert code == 0, err
    got = tmp_path / f"py.{ext}"
    v = bake_quietly(BOX, env, output=got, **options)
    assert got.read_bytes() == want.read_bytes()
    again = tmp_path / f"again.{ext}"
    v.write(again)
    assert again.read_bytes() == want.read_bytes()


def test_the_properties_are_the_files(cli, tmp_path, baked):
    v = shlight.Volume.load(baked["full"])
    assert (v.lmax, v.resolution, v.probe_count) == (2, (4, 2, 4), 32)
    assert v.relightable and v.has_visibility
    assert (v.scene, v.environment, v.frame) == ("cornell_box.obj", "park.exr", "y-up")
    # The rays per probe: a whole stratified grid of about 256.
    assert (v.bounces, v.seed) == (2, 0) and 200 < v.samples <= 256
    assert v.valid.dtype == np.bool_ and v.valid.shape == (32,)
    assert v.radiance.shape == (32, 9, 3) and v.radiance.dtype == np.float32
    # Probe k sits at its cell's centre, x fastest, plus its offset; the
    # Cornell box moves some of them (the CLI's note says two).
    lo, hi = (np.array(b, np.float64) for b in v.bounds)
    nx, ny, nz = v.resolution
    z, y, x = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    ijk = np.stack([x.ravel(), y.ravel(), z.ravel()], 1)
    centres = lo + (ijk + 0.5) * (hi - lo) / [nx, ny, nz]
    assert v.offsets.shape == (32, 3)
    assert np.count_nonzero(np.abs(v.offsets).max(1)) == 2
    assert np.allclose(v.positions, centres + v.offsets, atol=1e-6)
    # The CLI's JSON form says the same.
    js = tmp_path / "v.json"
    v.write(js)
    doc = json.loads(js.read_text())
    assert doc["valid"] == v.valid.tolist()
    assert (doc["samples"], doc["lmax"]) == (v.samples, v.lmax)
    plain = shlight.Volume.load(baked["plain"])
    assert not plain.has_visibility and plain.offsets is not None
    assert "Volume(resolution=(4, 2, 4)" in repr(v)


@pytest.mark.parametrize("lookup", LOOKUPS)
def test_irradiance_equals_sample(cli, tmp_path, baked, lookup):
    v = shlight.Volume.load(baked["full"])
    points, normals = points_and_normals(v, 400, seed=5)
    want = cli_sample(cli, tmp_path, baked["full"], points, normals, "--lookup", lookup)
    got = v.irradiance(points, normals, lookup=lookup)
    assert got.dtype == np.float64 and got.shape == (400, 3)
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=0)
    # Not all zero: the points inside the box are lit.
    assert (got > 0).any()
    # float32 input, and lists, read the same.
    np.testing.assert_array_equal(
        v.irradiance(points.astype(np.float32), normals.tolist(), lookup=lookup),
        v.irradiance(points.astype(np.float32).astype(np.float64), normals, lookup=lookup),
    )


@pytest.mark.parametrize("lookup,lmax", [("shlight", 1), ("trilinear", 0), ("bevy", 1), ("threejs", 1)])
def test_irradiance_to_a_lower_lmax_equals_sample(cli, tmp_path, baked, lookup, lmax):
    v = shlight.Volume.load(baked["full"])
    points, normals = points_and_normals(v, 100, seed=6)
    want = cli_sample(cli, tmp_path, baked["full"], points, normals, "--lookup", lookup, "--lmax", str(lmax))
    got = v.irradiance(points, normals, lookup=lookup, lmax=lmax)
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=0)
    assert not np.array_equal(got, v.irradiance(points, normals, lookup=lookup))


def test_a_file_without_distance_maps_is_trilinear(cli, tmp_path, baked):
    v = shlight.Volume.load(baked["plain"])
    points, normals = points_and_normals(v, 200, seed=7)
    want = cli_sample(cli, tmp_path, baked["plain"], points, normals, "--lookup", "shlight")
    got = v.irradiance(points, normals)
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=0)
    np.testing.assert_array_equal(got, v.irradiance(points, normals, lookup="trilinear"))


def test_relight_equals_sample_env(cli, tmp_path, baked):
    v = shlight.Volume.load(baked["full"])
    points, normals = points_and_normals(v, 300, seed=8)
    with pytest.warns(UserWarning, match="negative texels"):
        lit = v.relight(SKY)
    for lookup in ["shlight", "threejs"]:
        want = cli_sample(cli, tmp_path, baked["full"], points, normals, "--env", SKY, "--lookup", lookup)
        np.testing.assert_allclose(lit.irradiance(points, normals, lookup=lookup), want, rtol=RTOL, atol=0)
    # A new Volume: the loaded one keeps park's light.
    assert not np.array_equal(lit.radiance, v.radiance)
    np.testing.assert_array_equal(v.radiance, shlight.Volume.load(baked["full"]).radiance)
    # A coefficient file, and the SH read from it, relight as the CLI does.
    coeffs = tmp_path / "sky.json"
    code, _, err = run_cli(cli, "project", SKY, "--lmax", "2", "-o", coeffs)
    assert code == 0, err
    want = cli_sample(cli, tmp_path, baked["full"], points, normals, "--env", coeffs)
    np.testing.assert_allclose(v.relight(coeffs).irradiance(points, normals), want, rtol=RTOL, atol=0)
    np.testing.assert_allclose(
        v.relight(shlight.load(coeffs)).irradiance(points, normals), want, rtol=RTOL, atol=0
    )
    # Relit under its own bake's light, the file's radiance comes back.
    with pytest.warns(UserWarning, match="negative texels"):
        again = lit.relight(PARK)
    np.testing.assert_array_equal(again.radiance, v.radiance)


def test_bad_points_raise(baked):
    v = shlight.Volume.load(baked["full"])
    p = np.full((4, 3), 0.25)
    n = np.tile([0.0, 1.0, 0.0], (4, 1))
    with pytest.raises(ValueError, match=r"points must have shape \(N, 3\), not \[4, 2\]"):
        v.irradiance(p[:, :2], n)
    with pytest.raises(ValueError, match=r"normals must be an \(N, 3\) array"):
        v.irradiance(p, "up")
    with pytest.raises(shlight.ShlightError, match="4 points but 3 normals: one normal per point"):
        v.irradiance(p, n[:3])
    bad = p.copy()
    bad[2, 1] = np.nan
    with pytest.raises(shlight.ShlightError, match="point 2 is not finite"):
        v.irradiance(bad, n)
    zero = n.copy()
    zero[1] = 0.0
    with pytest.raises(shlight.ShlightError, match="normal 1 is not a direction"):
        v.irradiance(p, zero)
    with pytest.raises(shlight.ShlightError, match=r'unknown lookup "unity" \(expected shlight, trilinear, bevy, threejs\)'):
        v.irradiance(p, n, lookup="unity")
    with pytest.raises(shlight.ShlightError, match=r"lookup=threejs: lmax=3: three.js's LightProbeGrid holds nine coefficients per probe, lmax 2 at most"):
        v.irradiance(p, n, lookup="threejs", lmax=3)
    with pytest.raises(shlight.ShlightError, match=r"lookup=shlight: lmax=5: volumes are shaded to lmax 4 at most"):
        v.irradiance(p, n, lmax=5)


def test_static_volumes_and_bad_lights_are_refused(cli, tmp_path, baked):
    static = tmp_path / "static.shvol"
    code, _, err = run_cli(cli, "volume", BOX, "--env", PARK, *SMALL_FLAGS, "--static", "-o", static)
    assert code == 0, err
    v = shlight.Volume.load(static)
    assert not v.relightable
    points, normals = points_and_normals(v, 10, seed=9)
    out = tmp_path / "x.json"
    pts = tmp_path / "p.json"
    pts.write_text(json.dumps({"points": points.tolist(), "normals": normals.tolist()}))
    code, _, err = run_cli(cli, "sample", static, "--points", pts, "--env", SKY, "-o", out)
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            v.relight(SKY)
    assert "cannot be relit" in str(e.value)
    # The same message, naming the setting as each front end spells it.
    assert cli_error(err) == f"{static}: {e.value}".replace("baked static", "baked --static")
    full = shlight.Volume.load(baked["full"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        irradiance = shlight.project(SKY).irradiance()
        zh3 = shlight.project(SKY, encoding="zh3")
    with pytest.raises(shlight.ShlightError, match="holds irradiance"):
        full.relight(irradiance)
    with pytest.raises(shlight.ShlightError, match="kept as zh3"):
        full.relight(zh3)
    with pytest.raises(ValueError, match="env must be a path"):
        full.relight(3.5)
    missing = tmp_path / "missing.exr"
    code, _, err = run_cli(cli, "sample", baked["full"], "--points", pts, "--env", missing, "-o", out)
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        full.relight(missing)
    assert str(e.value) == cli_error(err)
    with pytest.raises(shlight.ShlightError, match=r'up="x"'):
        full.relight(SKY, up="x")


def test_missing_and_bad_files_are_the_clis_errors(cli, tmp_path):
    out = tmp_path / "x.json"
    pts = tmp_path / "p.json"
    pts.write_text(json.dumps({"points": [[0, 0, 0]], "normals": [[0, 1, 0]]}))
    missing = tmp_path / "missing.shvol"
    code, _, err = run_cli(cli, "sample", missing, "--points", pts, "-o", out)
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.Volume.load(missing)
    assert str(e.value) == cli_error(err)
    garbage = tmp_path / "garbage.shvol"
    garbage.write_bytes(b"not a volume")
    code, _, err = run_cli(cli, "sample", garbage, "--points", pts, "-o", out)
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.Volume.load(garbage)
    assert str(e.value) == cli_error(err)


def test_bake_refusals_are_the_clis(cli, tmp_path):
    out = tmp_path / "x.shvol"

    def both(flags, scene=BOX, env=PARK, **options):
        code, _, err = run_cli(cli, "volume", scene, "--env", env, *flags, "-o", out)
        assert code != 0
        with pytest.raises(shlight.ShlightError) as e:
            bake_quietly(scene, env, **options)
        return str(e.value), cli_error(err)

    got, want = both(["--lmax", "9"], lmax=9)
    assert got == want.replace("--lmax 9", "lmax=9")
    got, want = both([], scene=tmp_path / "missing.obj")
    assert got == want
    got, want = both([], env=tmp_path / "missing.exr")
    assert got == want
    coeffs = tmp_path / "l1.json"
    code, _, err = run_cli(cli, "project", SKY, "--lmax", "1", "-o", coeffs)
    assert code == 0, err
    got, want = both(["--resolution", "2x2x2"], env=coeffs, resolution=(2, 2, 2))
    assert got == want and "holds coefficients to lmax 1, the bake needs 2" in got
    got, want = both(["--resolution", "2x2x2", "--samples", "0"], resolution=(2, 2, 2), samples=0)
    assert got == want == "samples must be at least 1"
    got, want = both(["--resolution", "0x2x2"], resolution="0x2x2")
    assert got == want
    got, want = both(["--resolution", "2x2x2", "--bounds=1,1,1:0,0,0"], resolution=(2, 2, 2), bounds="1,1,1:0,0,0")
    assert got == want
    with pytest.raises(shlight.ShlightError, match="each count must be at least 1"):
        shlight.bake_volume(BOX, PARK, resolution=(0, 2, 2))
    with pytest.raises(shlight.ShlightError, match="min must be below max"):
        shlight.bake_volume(BOX, PARK, bounds=((1, 1, 1), (0, 0, 0)))
    with pytest.raises(ValueError, match=r"resolution must be \(nx, ny, nz\)"):
        shlight.bake_volume(BOX, PARK, resolution=(2, 2))
    with pytest.raises(shlight.ShlightError, match=r"albedo=\[1.5, 1.5, 1.5\]"):
        shlight.bake_volume(BOX, PARK, albedo=1.5)
    with pytest.raises(shlight.ShlightError, match="invalid_backfaces 2 is not within"):
        bake_quietly(BOX, PARK, resolution=(2, 2, 2), samples=16, surface_samples=16, invalid_backfaces=2.0)
