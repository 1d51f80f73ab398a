"""Arrays equal files: the same texels give the same coefficients bit for
bit however they are given (float32 in place, float64 in place, a strided
view copied, six face arrays against the CLI's six face files)."""

import warnings

import numpy as np
import pytest

import shlight

from conftest import MAPS, run_cli


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


@pytest.mark.parametrize("options", [{}, {"lmax": 6, "up": "z"}, {"method": "montecarlo", "samples": 2048}])
def test_array_input_equals_file_input(options):
    for m in MAPS[:3]:
        from_file = shlight.project(str(m), **options)
        img = shlight.read_image(m)
        assert img.dtype == np.float32 and img.shape == (256, 512, 3)
        for array in (img, img.astype(np.float64), np.asfortranarray(img), img[:, ::-1][:, ::-1]):
            sh = shlight.project(array, **options)
            assert np.array_equal(sh.coefficients, from_file.coefficients), (m, array.dtype, array.flags)


def test_the_array_is_read_in_place_and_left_as_it_was():
    img = shlight.read_image(MAPS[0])
    before = img.copy()
    shlight.project(img, 4)
    assert img.flags.writeable and np.array_equal(img, before)


def test_six_face_arrays_equal_the_clis_face_files(cli, tmp_path):
    light = shlight.project(str(MAPS[1]), 4)
    strip = shlight.render(light, 16, layout="strip")
    assert strip.shape == (16, 96, 3)
    faces = [np.ascontiguousarray(strip[:, 16 * k : 16 * (k + 1)]) for k in range(6)]
    for name, face in zip(["px", "nx", "py", "ny", "pz", "nz"], faces):
        shlight.write_image(tmp_path / f"sky_{name}.exr", face)
    out = tmp_path / "cli.json"
    code, _, err = run_cli(cli, "project", tmp_path / "sky_{face}.exr", "--lmax", "4", "-o", out)
    assert code == 0, err
    want = shlight.load(out).coefficients
    assert np.array_equal(shlight.project(faces, 4).coefficients, want)
    assert np.array_equal(shlight.project([f.astype(np.float64) for f in faces], 4).coefficients, want)
    assert np.array_equal(shlight.project(str(tmp_path / "sky_{face}.exr"), 4).coefficients, want)
    # The strip itself, one array in the strip layout, is the same cube.
    assert np.array_equal(shlight.project(strip, 4, layout="strip").coefficients, want)


def test_read_and_write_image_round_trip(tmp_path):
    img = shlight.read_image(MAPS[2])
    shlight.write_image(tmp_path / "copy.exr", img)
    assert np.array_equal(shlight.read_image(tmp_path / "copy.exr"), img)
