"""The numbers against independent routes: a numpy projection written from
docs/conventions.md, rotation checked by evaluation at R a, irradiance
against Ramamoorthi & Hanrahan's A_l, render against evaluation at the
texel directions of docs/conventions.md."""

import math
import warnings

import numpy as np
import pytest

import shlight

from conftest import MAPS
from reference import equirect_directions, project_l2

# The numpy reference sums the same texel x basis x solid-angle products in
# another order (einsum against shlight's ring transform): agreement to
# float64 rounding of a sum of 131072 terms of magnitude up to ~1e3.
SUM_ORDER_RELATIVE = 1e-9
# Rotations of lmax-4 expansions in float64 (Ivanic-Ruedenberg recurrences):
# rounding of a few hundred products.
ROTATION_TOLERANCE = 1e-11
# render writes float32 texels: relative rounding 6e-8 of values up to ~10.
RENDER_F32 = 1e-5


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


@pytest.mark.parametrize("up", ["y", "z"])
def test_projection_equals_a_numpy_projection_from_the_conventions(up):
    for m in MAPS:
        img = shlight.read_image(m)
        want = project_l2(img, up)
        got = shlight.project(img, 2, up=up).coefficients
        scale = np.abs(want).max()
        assert np.abs(got - want).max() <= SUM_ORDER_RELATIVE * scale, m


def random_rotation(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def quat_matrix(q):
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def test_a_rotated_light_from_a_comes_from_r_a():
    rng = np.random.default_rng(5)
    sh = shlight.project(str(MAPS[2]), 4)
    dirs = rng.normal(size=(64, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    before = sh.eval(dirs)
    scale = np.abs(before).max()
    for _ in range(3):
        q = random_rotation(rng)
        r = quat_matrix(q)
        for turned in (sh.rotate(r), sh.rotate(q)):
            after = turned.eval(dirs @ r.T)  # row i is R a_i
            assert np.abs(after - before).max() <= ROTATION_TOLERANCE * scale
    # yaw:90 about +Y (y-up) takes +X to -Z, as `--rotate yaw:90`.
    turned = shlight.project(str(MAPS[2]), 4, rotate="yaw:90")
    assert np.allclose(turned.eval([0, 0, -1]), sh.eval([1, 0, 0]), rtol=0, atol=ROTATION_TOLERANCE * scale)
    assert turned.to_json().count('"spec": "yaw:90"') == 1


def test_rotate_refuses_what_is_no_rotation():
    sh = shlight.project(str(MAPS[0]), 2)
    for bad in (np.diag([1.0, 1.0, -1.0]), 2 * np.eye(3), [0, 0, 0, 0], np.eye(4), [1, 2]):
        with pytest.raises(ValueError):
            sh.rotate(bad)


def test_irradiance_is_the_clamped_cosine_convolution():
    # Ramamoorthi & Hanrahan 2001, eq. 8-9: A_0 = pi, A_1 = 2 pi / 3,
    # A_2 = pi / 4, A_3 = 0, A_4 = -pi / 24 (A_l for even l >= 2:
    # 2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2)).
    def a(l):
        if l == 1:
            return 2 * math.pi / 3
        if l % 2:
            return 0.0
        return (
            2 * math.pi * (-1) ** (l // 2 - 1) / ((l + 2) * (l - 1))
            * math.factorial(l) / (2**l * math.factorial(l // 2) ** 2)
        )

    assert a(0) == pytest.approx(math.pi) and a(2) == pytest.approx(math.pi / 4)
    assert a(4) == pytest.approx(-math.pi / 24)
    sh = shlight.project(str(MAPS[3]), 6)
    e = sh.irradiance()
    assert e.quantity == "irradiance" and sh.quantity == "radiance"
    scale = np.array([a(l) for l in range(7) for _ in range(2 * l + 1)])[:, None]
    assert np.allclose(e.coefficients, scale * sh.coefficients, rtol=1e-14, atol=0)
    direct = shlight.project(str(MAPS[3]), 6, quantity="irradiance")
    assert np.array_equal(direct.coefficients, e.coefficients)
    mc = shlight.project(str(MAPS[3]), 2, method="montecarlo", samples=1024)
    assert np.allclose(mc.irradiance().std_error, np.abs(scale[:9]) * mc.std_error, rtol=1e-14, atol=0)


@pytest.mark.parametrize("up", ["y", "z"])
def test_render_evaluates_at_the_documented_texel_directions(up):
    sh = shlight.project(str(MAPS[-1]), 3, up=up)
    img = shlight.render(sh, (64, 32))
    assert img.shape == (32, 64, 3) and img.dtype == np.float32
    d = equirect_directions(64, 32, up).reshape(-1, 3)
    want = sh.eval(d).reshape(32, 64, 3)
    assert np.abs(img - want).max() <= RENDER_F32 * np.abs(want).max()
    e = shlight.render(sh, 32, irradiance=True)
    assert np.abs(e - sh.irradiance().eval(d).reshape(32, 64, 3)).max() <= RENDER_F32 * np.abs(e).max()


def test_window_scales_each_band_as_the_cli_window():
    sh = shlight.project(str(MAPS[0]), 4)
    w = sh.window("hanning:5")
    factor = np.array([(1 + math.cos(math.pi * l / 5)) / 2 for l in range(5) for _ in range(2 * l + 1)])
    assert np.allclose(w.coefficients, factor[:, None] * sh.coefficients, rtol=1e-15, atol=0)
    assert np.array_equal(
        shlight.project(str(MAPS[0]), 4, window="hanning:5").coefficients, w.coefficients
    )
