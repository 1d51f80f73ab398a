"""project_many equals one project per path, bit for bit, on every core."""

import warnings

import numpy as np

import shlight

from conftest import MAPS


def test_project_many_equals_project_per_path():
    paths = [str(m) for m in MAPS] * 3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        many = shlight.project_many(paths, 4, window="auto", progress=True)
        one = [shlight.project(p, 4, window="auto") for p in paths]
    assert len(many) == len(paths)
    for a, b in zip(many, one):
        assert a.to_json() == b.to_json()


def test_sh_pickles_bit_for_bit():
    import pickle

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sh = shlight.project(str(MAPS[0]), 3, method="montecarlo", samples=1024)
    back = pickle.loads(pickle.dumps(sh))
    assert np.array_equal(back.coefficients, sh.coefficients)
    assert np.array_equal(back.std_error, sh.std_error)
    assert back.to_json() == sh.to_json()
