"""shlight.bake_transfer bakes what `shlight prt` bakes: Transfer.save
writes the CLI's .shprt file byte for byte, for every mode."""

import numpy as np
import pytest

import shlight

from conftest import ROOT, cli_error, run_cli

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
