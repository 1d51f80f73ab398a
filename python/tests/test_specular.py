"""shlight.prefilter and shlight.dfg write what the CLI writes, byte for byte."""

import shlight

from conftest import MAPS, run_cli


def test_prefilter_writes_the_clis_files(cli, tmp_path):
    m = MAPS[0]
    ours = tmp_path / "py"
    files = shlight.prefilter(str(m), ours, engine="bevy", size=16, samples=32)
    assert len(files) == 5 * 6
    assert files[0].endswith("m0_px.exr") and files[-1].endswith("m4_nz.exr")
    code, _, err = run_cli(
        cli, "prefilter", m, "-o", f"{tmp_path / 'cli'}/", "--for", "bevy", "--size", "16", "--samples", "32", "-q"
    )
    assert code == 0, err
    for f in files:
        name = f.split("/")[-1]
        assert (tmp_path / "cli" / name).read_bytes() == (ours / name).read_bytes(), name


def test_dfg_writes_the_clis_table(cli, tmp_path):
    shlight.dfg(tmp_path / "py.exr", engine="unreal", size=8, samples=64)
    code, _, err = run_cli(cli, "dfg", "-o", tmp_path / "cli.exr", "--for", "unreal", "--size", "8", "--samples", "64")
    assert code == 0, err
    assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()


def test_bad_settings_raise_naming_them(tmp_path):
    import pytest

    with pytest.raises(shlight.ShlightError, match="power of two"):
        shlight.prefilter(str(MAPS[0]), tmp_path / "x", size=48)
    with pytest.raises(shlight.ShlightError, match="unknown engine"):
        shlight.dfg(tmp_path / "d.exr", engine="godot")
