"""shlight.bake_transfer bakes what `shlight prt` bakes: Transfer.save
writes the CLI's .shprt file byte for byte, for every mode."""

import numpy as np
import pytest

import shlight

from conftest import ROOT, cli_error, run_cli
from reference import sh_basis_l2

BUNNY = ROOT / "meshes" / "bunny.obj"
BOX = ROOT / "meshes" / "cornell_box.obj"


@pytest.mark.parametrize(
    "mesh,flags,options",
    [
        (BUNNY, ["--mode", "unshadowed"], {"mode": "unshadowed"}),
        (BUNNY, ["--mode", "shadowed"], {"mode": "shadowed"}),
        (BUNNY, ["--mode", "interreflected"], {"mode": "interreflected"}),
        (BUNNY, ["--lmax", "2", "--albedo", "0.5,0.6,0.7", "--seed", "9"], {"lmax": 2, "albedo": (0.5, 0.6, 0.7), "seed": 9}),
        (BOX, ["--mode", "interreflected", "--bounces", "1"], {"mode": "interreflected", "bounces": 1}),
    ],
    ids=["unshadowed", "shadowed", "interreflected", "rgb albedo", "vertex colours"],
)
def test_saved_bakes_equal_the_clis_files(cli, tmp_path, mesh, flags, options):
    want = tmp_path / "cli.shprt"
    code, _, err = run_cli(cli, "prt", mesh, "--samples", "64", *flags, "-o", want)
    assert code == 0, err
    t = shlight.bake_transfer(str(mesh), samples=64, **options)
    got = tmp_path / "py.shprt"
    t.save(got)
    assert got.read_bytes() == want.read_bytes()
    lmax = options.get("lmax", 4)
    assert (t.lmax, t.mode) == (lmax, options.get("mode", "shadowed"))
    c = t.coefficients
    assert c.dtype == np.float32
    assert c.shape == (t.vertex_count, t.channels, (lmax + 1) ** 2)
    assert t.channels == (3 if "albedo" in options or mesh == BOX else 1)
    assert np.isfinite(c).all() and (c[:, :, 0] > 0).any()


def test_bake_refusals_are_the_clis(cli, tmp_path):
    out = tmp_path / "x.shprt"
    code, _, err = run_cli(cli, "prt", BUNNY, "--bounces", "3", "-o", out)
    assert code != 0 and "--bounces needs --mode interreflected" in cli_error(err)
    with pytest.raises(shlight.ShlightError, match=r'bounces needs mode="interreflected"'):
        shlight.bake_transfer(BUNNY, bounces=3)
    code, _, err = run_cli(cli, "prt", BUNNY, "--lmax", "33", "-o", out)
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.bake_transfer(BUNNY, lmax=33)
    assert str(e.value) == cli_error(err).replace("--lmax 33", "lmax=33")
    for kwargs in ({"samples": 0}, {"mode": "ambient"}, {"albedo": 1.5}, {"albedo": (0.5, 0.5)}):
        with pytest.raises(shlight.ShlightError):
            shlight.bake_transfer(BUNNY, **kwargs)
    missing = tmp_path / "missing.obj"
    code, _, err = run_cli(cli, "prt", missing, "-o", out)
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.bake_transfer(missing)
    assert str(e.value) == cli_error(err)


def bake_glossy_and_light(cli, tmp_path, brdf):
    """`shlight prt` of the bunny, glossy with `brdf`, lmax 2, and the park
    projected to lmax 2: the two paths."""
    glossy = tmp_path / "g.shprt"
    code, _, err = run_cli(
        cli, "prt", BUNNY, "--mode", "glossy", "--brdf", brdf, "--lmax", "2",
        "--samples", "64", "-o", glossy,
    )
    assert code == 0, err
    light = tmp_path / "park.json"
    code, _, err = run_cli(cli, "project", ROOT / "envmaps" / "park.exr", "--lmax", "2", "-o", light)
    assert code == 0, err
    return glossy, light


def test_glossy_exit_radiance_is_the_clis_and_the_formula(cli, tmp_path):
    """Transfer.load reads a glossy .shprt file; exit_radiance gives what
    `shlight sample --view/--eye` gives, and the definition written out
    here: sum_lm Lambda_l (M L)_lm Y_lm(R), R the mirror of the view
    about the normal, Lambda = 1, (S+1)/(S+2), S/(S+3)."""
    glossy, light = bake_glossy_and_light(cli, tmp_path, "phong:20")
    t = shlight.Transfer.load(glossy)
    assert (t.mode, t.brdf, t.lmax, t.channels) == ("glossy", "phong:20", 2, 1)
    m = t.matrices
    assert m.shape == (t.vertex_count, 1, 9, 9)
    with pytest.raises(shlight.ShlightError, match="matrices"):
        t.coefficients
    view = np.array([0.2, 0.4, 1.0])
    got = t.exit_radiance(str(light), view=tuple(view))
    assert got.shape == (t.vertex_count, 3)
    # The CLI's sample, on the same file, light and view.
    out = tmp_path / "s.json"
    code, _, err = run_cli(cli, "sample", glossy, "--light", light, "--view", "0.2,0.4,1", "-o", out)
    assert code == 0, err
    import json
    assert np.allclose(got, np.array(json.loads(out.read_text())["radiance"]), rtol=1e-12, atol=1e-12)
    # The formula, in numpy.
    L = shlight.load(light).coefficients
    n = t.normals.astype(np.float64)
    w = view / np.linalg.norm(view)
    r = 2 * (n @ w)[:, None] * n - w
    y = sh_basis_l2(r / np.linalg.norm(r, axis=1)[:, None])
    s = 20.0
    lam = np.array([1.0] + [(s + 1) / (s + 2)] * 3 + [s / (s + 3)] * 5)
    tr = np.einsum("vij,jc->vic", m[:, 0].astype(np.float64), L)
    want = np.einsum("vic,vi->vc", tr, y * lam)
    assert np.allclose(got, want, rtol=1e-5, atol=1e-5 * np.abs(want).max())
    # An eye: each vertex's own direction to it.
    eye = np.array([0.0, 1.0, 5.0])
    by_eye = t.exit_radiance(str(light), eye=tuple(eye))
    w = eye - t.positions.astype(np.float64)
    w /= np.linalg.norm(w, axis=1)[:, None]
    r = 2 * np.sum(n * w, axis=1)[:, None] * n - w
    want = np.einsum("vic,vi->vc", tr, sh_basis_l2(r / np.linalg.norm(r, axis=1)[:, None]) * lam)
    assert np.allclose(by_eye, want, rtol=1e-5, atol=1e-5 * np.abs(want).max())
    # A diffuse base: albedo / pi sum A_l T_lm Y_lm(n), the CLI's --albedo.
    based = t.exit_radiance(str(light), eye=tuple(eye), albedo=(0.2, 0.4, 0.6))
    a_l = np.array([np.pi] + [2 * np.pi / 3] * 3 + [np.pi / 4] * 5)
    e_n = np.einsum("vic,vi->vc", tr, sh_basis_l2(n / np.linalg.norm(n, axis=1)[:, None]) * a_l)
    want_base = np.array([0.2, 0.4, 0.6]) / np.pi * e_n
    assert np.allclose(based - by_eye, want_base, rtol=1e-5, atol=1e-5 * np.abs(want_base).max())
    code, _, err = run_cli(
        cli, "sample", glossy, "--light", light, "--eye", "0,1,5", "--albedo", "0.2,0.4,0.6",
        "-o", out,
    )
    assert code == 0, err
    assert np.allclose(based, np.array(json.loads(out.read_text())["radiance"]), rtol=1e-12, atol=1e-12)
    # Refusals.
    with pytest.raises(shlight.ShlightError, match="seen from somewhere"):
        t.exit_radiance(str(light))
    with pytest.raises(shlight.ShlightError, match="zero length"):
        t.exit_radiance(str(light), view=(0, 0, 0))
    with pytest.raises(shlight.ShlightError, match="not both"):
        t.exit_radiance(str(light), view=(0, 0, 1), eye=(0, 0, 1))
    # A diffuse file ignores the view.
    d = shlight.bake_transfer(BUNNY, lmax=2, samples=64)
    assert d.brdf is None and d.matrices is None
    assert np.array_equal(d.exit_radiance(str(light)), d.exit_radiance(str(light), view=(1, 2, 3)))
    with pytest.raises(shlight.ShlightError, match="albedo is in its transfer"):
        d.exit_radiance(str(light), albedo=0.5)


def test_a_compressed_glossy_file_shades_as_the_cli_and_reconstructs(cli, tmp_path):
    """A CPCA-compressed glossy file (shlight prt --compress): exit_radiance
    gives what shlight sample gives; with a cluster per vertex its matrices
    are the uncompressed file's."""
    files = {}
    for name, extra in [("plain", []), ("each", ["--compress", "cpca:5000,0"]), ("small", ["--compress", "cpca:8,4"])]:
        files[name] = tmp_path / f"{name}.shprt"
        code, _, err = run_cli(
            cli, "prt", BUNNY, "--mode", "glossy", "--brdf", "phong:10", "--lmax", "2",
            "--samples", "64", *extra, "-o", files[name],
        )
        assert code == 0, err
    light = tmp_path / "park.json"
    code, _, err = run_cli(cli, "project", ROOT / "envmaps" / "park.exr", "--lmax", "2", "-o", light)
    assert code == 0, err
    plain, each, small = (shlight.Transfer.load(files[n]) for n in ("plain", "each", "small"))
    assert np.array_equal(each.matrices, plain.matrices)
    assert small.matrices.shape == plain.matrices.shape
    assert not np.array_equal(small.matrices, plain.matrices)
    out = tmp_path / "s.json"
    code, _, err = run_cli(cli, "sample", files["small"], "--light", light, "--eye", "0,1,4", "-o", out)
    assert code == 0, err
    import json
    want = np.array(json.loads(out.read_text())["radiance"])
    got = small.exit_radiance(str(light), eye=(0, 1, 4))
    assert np.allclose(got, want, rtol=1e-12, atol=1e-12)
    assert np.allclose(each.exit_radiance(str(light), eye=(0, 1, 4)), plain.exit_radiance(str(light), eye=(0, 1, 4)), rtol=1e-9, atol=1e-12)


def ggx_brdf_cos(n, wo, wi, alpha, f0):
    """f(w_o, w_i) (n.w_i) of the GGX microfacet BRDF (docs/shprt.md):
    GGX D, Smith's height-correlated G_2, Schlick's F; wi is (k, 3)."""
    mo, mi = float(n @ wo), wi @ n
    h = wi + wo
    h /= np.linalg.norm(h, axis=1)[:, None]
    a2 = alpha * alpha
    c = h @ n
    d = a2 / (np.pi * (c * c * (a2 - 1) + 1) ** 2)
    lam = lambda mu: 0.5 * (-1 + np.sqrt(1 + a2 * (1 - mu * mu) / (mu * mu)))
    g2 = 1 / (1 + lam(mo) + lam(mi))
    f = f0 + (1 - f0) * (1 - h @ wo) ** 5
    return d * g2 * f / (4 * mo)


def test_ggx_exit_radiance_is_the_clis_and_the_brdf_integrated(cli, tmp_path):
    """A `--brdf ggx:0.3,0.04` file: exit_radiance gives what `shlight
    sample --eye` gives, and at a few vertices the transferred radiance
    M L integrated against the BRDF over the hemisphere, here in numpy."""
    glossy, light = bake_glossy_and_light(cli, tmp_path, "ggx:0.3,0.04")
    t = shlight.Transfer.load(glossy)
    assert t.brdf == "ggx:0.3,0.04"
    eye = np.array([0.3, 1.0, 4.0])
    got = t.exit_radiance(str(light), eye=tuple(eye))
    out = tmp_path / "s.json"
    code, _, err = run_cli(cli, "sample", glossy, "--light", light, "--eye", "0.3,1,4", "-o", out)
    assert code == 0, err
    import json
    assert np.allclose(got, np.array(json.loads(out.read_text())["radiance"]), rtol=1e-12, atol=1e-12)
    L = shlight.load(light).coefficients
    m = t.matrices
    # The hemisphere about each normal: midpoints in n.w and azimuth.
    rows, cols = 400, 800
    z = (np.arange(rows) + 0.5) / rows
    phi = 2 * np.pi * (np.arange(cols) + 0.5) / cols
    z, phi = np.meshgrid(z, phi, indexing="ij")
    s = np.sqrt(1 - z * z)
    local = np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1).reshape(-1, 3)
    weight = 2 * np.pi / (rows * cols)
    normals = t.normals.astype(np.float64)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    towards = eye - t.positions.astype(np.float64)
    towards /= np.linalg.norm(towards, axis=1)[:, None]
    facing = np.flatnonzero(np.sum(normals * towards, axis=1) > 0.05)
    checked = 0
    for v in facing[:: len(facing) // 6][:6]:
        n, wo = normals[v], towards[v]
        u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        u /= np.linalg.norm(u)
        b = np.cross(n, u)
        w = local @ np.stack([u, b, n])
        tr = m[v, 0].astype(np.float64) @ L
        radiance = sh_basis_l2(w) @ tr
        want = (ggx_brdf_cos(n, wo, w, 0.3, 0.04)[:, None] * radiance).sum(axis=0) * weight
        assert np.allclose(got[v], want, rtol=2e-3, atol=2e-3 * np.abs(want).max()), (v, got[v], want)
        checked += 1
    assert checked == 6
