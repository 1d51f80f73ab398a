"""Bad inputs raise clear exceptions (the CLI's messages for files), never
a crash."""

import warnings

import numpy as np
import pytest

import shlight

from conftest import MAPS, cli_error, run_cli


def test_wrong_shapes_and_dtypes():
    for shape in [(32, 64), (32, 64, 4), (32, 64, 3, 1), (0,)]:
        with pytest.raises(ValueError, match=r"shape \(H, W, 3\)"):
            shlight.project(np.zeros(shape, np.float32))
    for dtype in [np.int32, np.uint8, np.float16, np.complex64]:
        with pytest.raises(TypeError, match="float32 or float64"):
            shlight.project(np.zeros((32, 64, 3), dtype))
    with pytest.raises(TypeError, match="path"):
        shlight.project(3.5)
    with pytest.raises(ValueError, match="six face arrays"):
        shlight.project([np.zeros((4, 4, 3), np.float32)] * 5)
    with pytest.raises(shlight.ShlightError, match="fits no layout"):
        shlight.project(np.zeros((30, 70, 3), np.float32))
    with pytest.raises(shlight.ShlightError, match="square"):
        shlight.project([np.zeros((4, 4, 3), np.float32)] * 5 + [np.zeros((4, 5, 3), np.float32)])


def test_nan_arrays_are_refused_or_sanitized():
    img = np.ones((32, 64, 3), np.float32)
    img[3, 5, 1] = np.nan
    img[7, 2, 0] = np.inf
    with pytest.raises(shlight.ShlightError, match=r"<array>: 2 texels are NaN or infinite \(the first at x=5, y=3\)"):
        shlight.project(img)
    with pytest.warns(UserWarning, match="replaced 2 values"):
        sh = shlight.project(img, sanitize=True)
    assert np.isfinite(sh.coefficients).all()


def test_file_errors_carry_the_clis_messages(cli, tmp_path):
    img = shlight.read_image(MAPS[0])
    img[10, 20] = np.nan
    bad = tmp_path / "nan.exr"
    shlight.write_image(bad, img)
    missing = tmp_path / "missing.exr"
    text = tmp_path / "text.exr"
    text.write_text("not an image")
    for path in (bad, missing, text):
        code, _, err = run_cli(cli, "project", path, "-o", tmp_path / "out.json")
        assert code != 0
        with pytest.raises(shlight.ShlightError) as e:
            shlight.project(path)
        # The same message, naming the setting as each front end spells it.
        assert str(e.value) == cli_error(err).replace("--sanitize", "sanitize")
        assert str(path) in str(e.value)
    with pytest.raises(shlight.ShlightError) as e:
        shlight.project_many([MAPS[0], missing, bad, MAPS[1], text])
    msg = str(e.value)
    assert msg.startswith("3 of 5 inputs failed")
    for path in (missing, bad, text):
        assert str(path) in msg
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = shlight.project_many([MAPS[0], missing], errors="none")
    assert got[1] is None and got[0] is not None
    assert any(str(missing) in str(w.message) for w in caught)


def test_bad_options():
    m = str(MAPS[0])
    with pytest.raises(shlight.ShlightError, match=r"samples, seed only apply to method=\"montecarlo\""):
        shlight.project(m, samples=10, seed=3)
    for kwargs in ({"up": "x"}, {"layout": "cube"}, {"method": "exact"}, {"sampler": "halton", "method": "montecarlo"},
                   {"window": "gauss:2"}, {"quantity": "exitance"}, {"rotate": "spin:3"}):
        with pytest.raises(shlight.ShlightError):
            shlight.project(m, **kwargs)
    sh = shlight.project(m)
    with pytest.raises(ValueError, match="not a direction"):
        sh.eval([[0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        sh.eval(np.ones((4, 2)))
    with pytest.raises(shlight.ShlightError):
        shlight.render(sh, (64, 64))
    with pytest.raises(shlight.ShlightError, match="missing"):
        shlight.load("missing.json")
