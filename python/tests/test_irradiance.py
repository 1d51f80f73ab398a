"""shlight.irradiance equals the map `shlight irradiance MAP -o E.exr`
writes (the exact, every-texel irradiance) to float32, the precision of
the CLI's EXR; its refusals are the CLI's. (The output lies in the map's
own frame, so `up` and `mirror` turn the map and the normals together and
leave the image as it is; `sanitize` changes it.)"""

import numpy as np
import pytest

import shlight

from conftest import ENVMAPS, cli_error, run_cli

CASES = [
    (ENVMAPS / "sky.exr", [], {}),
    (ENVMAPS / "studio.exr", ["--up", "z", "--sanitize"], {"up": "z", "sanitize": True}),
]


@pytest.mark.parametrize("m,flags,options", CASES, ids=["sky", "studio sanitized"])
def test_the_exact_irradiance_equals_the_clis_map(cli, tmp_path, m, flags, options):
    out = tmp_path / "e.exr"
    code, _, err = run_cli(cli, "irradiance", m, "-o", out, "--size", "64x32", *flags)
    assert code == 0, err
    want = shlight.read_image(out)
    got = shlight.irradiance(str(m), size=(64, 32), **options)
    assert got.shape == (32, 64, 3) and got.dtype == np.float64
    assert (got > 0).all()
    assert np.array_equal(got.astype(np.float32), want)
    if options.get("sanitize"):
        # studio has negative texels: sanitizing them to 0 raises E.
        kept = shlight.irradiance(str(m), size=(64, 32))
        assert (got >= kept).all() and (got > kept).any()


def test_the_default_size_and_the_clis_refusals(cli, tmp_path):
    m = ENVMAPS / "sky.exr"
    assert shlight.irradiance(m).shape == (32, 64, 3)
    code, _, err = run_cli(cli, "irradiance", m, "-o", tmp_path / "e.exr", "--size", "64x64")
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.irradiance(m, size=(64, 64))
    assert cli_error(err) == "--size: " + str(e.value).split(": ", 1)[1]
    missing = tmp_path / "missing.exr"
    code, _, err = run_cli(cli, "irradiance", missing, "-o", tmp_path / "e.exr")
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.irradiance(missing)
    assert str(e.value) == cli_error(err)
    with pytest.raises(shlight.ShlightError, match='up="x"'):
        shlight.irradiance(m, up="x")
