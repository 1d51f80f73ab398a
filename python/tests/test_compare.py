"""shlight.compare returns the rows `shlight compare MAPS -o DIR` writes to
DIR/compare.json: the same keys and the same values."""

import json

import pytest

import shlight

from conftest import ENVMAPS, cli_error, run_cli


def test_compare_equals_the_clis_json(cli, tmp_path):
    maps = [ENVMAPS / "sky.exr", ENVMAPS / "studio.exr"]
    code, out, err = run_cli(cli, "compare", *maps, "--normals", "32x16", "-o", tmp_path / "cmp")
    assert code == 0, err
    want = json.loads((tmp_path / "cmp" / "compare.json").read_text())
    got = shlight.compare([str(m) for m in maps], normals=(32, 16))
    # Every encoding on each map: 10 cases and the ambient cube.
    assert len(want) == 22
    assert got == want
    assert [r["map"] for r in got] == ["sky"] * 11 + ["studio"] * 11
    assert {r["encoding"] for r in got} >= {"sh", "dominant+sh", "zh3", "ambient-cube"}


def test_compare_refuses_what_the_cli_refuses(cli, tmp_path):
    missing = tmp_path / "missing.exr"
    code, _, err = run_cli(cli, "compare", missing)
    assert code != 0
    with pytest.raises(shlight.ShlightError) as e:
        shlight.compare([missing])
    assert str(e.value) == cli_error(err)
    with pytest.raises(shlight.ShlightError, match="normals"):
        shlight.compare([ENVMAPS / "sky.exr"], normals=(0, 16))
