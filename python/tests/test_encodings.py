"""shlight.project(..., encoding=E) and the encoded light's irradiance_at
against the CLI: the coefficient file is `shlight project --encoding E`'s
byte for byte, and irradiance_at at the texel centres of a 32x16 equirect
grid is the map `shlight irradiance --encoding E` writes beside its output
(OUT-E.exr)."""

import warnings

import numpy as np
import pytest

import shlight

from conftest import ENVMAPS, cli_error, run_cli
from reference import equirect_directions

ENCODINGS = ["dominant+sh", "sloan+sh", "zh3", "zh3-hallucinated", "l1-nonlinear", "ambient-cube"]
# Two maps: one with a sun (dominant lights found), one without.
TWO_MAPS = [ENVMAPS / "sky.exr", ENVMAPS / "city.exr"]
SIZE = (32, 16)


def quietly(f, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return f(*args, **kwargs)


def cli_irradiance(cli, tmp_path, m, flags, suffix):
    """The CLI's `irradiance --size 32x16 FLAGS` map beside OUT (OUT-SUFFIX.exr)."""
    out = tmp_path / f"{m.stem}_{suffix.replace('+', '_')}.exr"
    code, _, err = run_cli(cli, "irradiance", m, "-o", out, "--size", f"{SIZE[0]}x{SIZE[1]}", *flags)
    assert code == 0, err
    beside = out.with_name(f"{out.stem}-{suffix}.exr")
    assert beside.exists(), sorted(p.name for p in tmp_path.iterdir())
    return shlight.read_image(beside).astype(np.float64)


def close(got, want, rel=1e-5):
    scale = np.abs(want).max()
    assert scale > 0
    err = np.abs(got - want).max() / scale
    assert err < rel, err


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_encoded_files_and_irradiance_equal_the_clis(cli, tmp_path, encoding):
    normals = equirect_directions(*SIZE).reshape(-1, 3)
    for m in TWO_MAPS:
        want = tmp_path / f"{m.stem}-cli.json"
        code, _, err = run_cli(cli, "project", m, "--encoding", encoding, "-o", want)
        assert code == 0, err
        sh = quietly(shlight.project, str(m), encoding=encoding)
        assert sh.encoding == encoding
        got = tmp_path / f"{m.stem}-py.json"
        sh.save(got)
        assert got.read_bytes() == want.read_bytes(), (m, encoding)
        assert shlight.load(want).encoding == encoding

        exact_e = cli_irradiance(cli, tmp_path, m, ["--encoding", encoding], encoding)
        e = sh.irradiance_at(normals)
        assert e.shape == normals.shape and e.dtype == np.float64
        close(e.reshape(SIZE[1], SIZE[0], 3), exact_e)
        # One direction gives (3,), and directions are normalised.
        assert np.allclose(sh.irradiance_at(3 * normals[5]), e[5], rtol=1e-12, atol=0)


def test_plain_sh_irradiance_at_is_the_convolved_radiance(cli, tmp_path):
    normals = equirect_directions(*SIZE).reshape(-1, 3)
    m = TWO_MAPS[0]
    want = cli_irradiance(cli, tmp_path, m, ["--sh", "2"], "sh")
    sh = quietly(shlight.project, str(m))
    assert sh.encoding == "sh"
    close(sh.irradiance_at(normals).reshape(SIZE[1], SIZE[0], 3), want)
    # An irradiance file is evaluated as it is: the same numbers.
    e = quietly(shlight.project, str(m), quantity="irradiance")
    assert e.encoding == "sh"
    close(e.irradiance_at(normals).reshape(SIZE[1], SIZE[0], 3), want)
    assert np.array_equal(e.irradiance_at(normals), e.eval(normals))


def test_project_many_takes_the_encoding():
    paths = [str(m) for m in TWO_MAPS]
    many = quietly(shlight.project_many, paths, encoding="zh3")
    for p, sh in zip(paths, many):
        assert sh.to_json() == quietly(shlight.project, p, encoding="zh3").to_json()


@pytest.mark.parametrize(
    "flags,options,what",
    [
        (["--quantity", "irradiance"], {"quantity": "irradiance"}, 'quantity="irradiance"'),
        (["--rotate", "yaw:30"], {"rotate": "yaw:30"}, "rotate"),
        (["--method", "montecarlo"], {"method": "montecarlo"}, 'method="montecarlo"'),
        (["--window", "hanning:4"], {"window": "hanning:4"}, "window"),
        (["--window", "auto"], {"window": "auto"}, "window"),
    ],
)
def test_the_clis_refusals(cli, tmp_path, flags, options, what):
    m = TWO_MAPS[0]
    code, _, err = run_cli(cli, "project", m, "--encoding", "zh3", *flags, "-o", tmp_path / "x.json")
    assert code != 0
    assert "cannot be combined with" in cli_error(err)
    with pytest.raises(shlight.ShlightError) as e:
        shlight.project(str(m), encoding="zh3", **options)
    assert str(e.value) == (
        'encoding="zh3" keeps radiance projected by quadrature in shlight\'s JSON file; '
        f"it cannot be combined with {what}"
    )
    # The same options with plain SH, and window="none", are fine.
    quietly(shlight.project, str(m), **options)
    quietly(shlight.project, str(m), encoding="zh3", window="none")


def test_unknown_encodings_and_the_coefficients_of_an_encoded_light():
    m = str(TWO_MAPS[0])
    with pytest.raises(shlight.ShlightError, match=r'encoding="zh4": unknown encoding'):
        shlight.project(m, encoding="zh4")
    sh = quietly(shlight.project, m, encoding="zh3")
    assert "encoding=\"zh3\"" in repr(sh)
    d = np.array([[0.0, 1.0, 0.0]])
    for call in [
        lambda: sh.eval(d),
        lambda: sh.irradiance(),
        lambda: sh.rotate(np.eye(3)),
        lambda: sh.window("hanning:4"),
        lambda: shlight.render(sh, 16),
    ]:
        with pytest.raises(shlight.ShlightError, match=r"kept as zh3, whose coefficients alone are not the light; irradiance_at"):
            call()
    # A plain SH still evaluates.
    plain = quietly(shlight.project, m)
    assert plain.eval(d).shape == (1, 3)
