"""examples/dask_dataset.py on a LocalCluster of 2 worker processes gives
project_many's coefficients bit for bit."""

import pathlib
import shutil
import subprocess
import sys
import warnings

import numpy as np

import shlight

from conftest import MAPS

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "dask_dataset.py"


def test_dask_example_equals_project_many(tmp_path):
    folder = tmp_path / "maps"
    folder.mkdir()
    for k, m in enumerate(MAPS * 2):
        shutil.copy(m, folder / f"{k:02d}-{m.name}")
    out = tmp_path / "coeffs.npz"
    r = subprocess.run(
        [sys.executable, str(EXAMPLE), str(folder), str(out), "--workers", "2", "--lmax", "4", "--up", "z"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    got = np.load(out)
    files = [str(f) for f in got["files"]]
    assert files == sorted(str(p) for p in folder.glob("*.exr")) and len(files) == 2 * len(MAPS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        want = shlight.project_many(files, 4, up="z")
    assert got["coefficients"].shape == (2 * len(MAPS), 25, 3) and got["coefficients"].dtype == np.float64
    assert np.array_equal(got["coefficients"], np.stack([s.coefficients for s in want]))
    assert str(got["frame"]) == "z-up" and int(got["lmax"]) == 4
