"""shlight.project equals `shlight project` on the bundled maps bit for
bit: the coefficient file Python writes is the CLI's file byte for byte,
and every export string is the CLI's `--format` output."""

import warnings

import numpy as np
import pytest

import shlight

from conftest import MAPS, run_cli

# (CLI flags, the same options for shlight.project)
OPTION_SETS = [
    ([], {}),
    (["--lmax", "8"], {"lmax": 8}),
    (["--lmax", "4", "--up", "z", "--quantity", "irradiance"], {"lmax": 4, "up": "z", "quantity": "irradiance"}),
    (["--lmax", "6", "--window", "auto", "--quantity", "irradiance"], {"lmax": 6, "window": "auto", "quantity": "irradiance"}),
    (["--window", "hanning:5", "--mirror"], {"window": "hanning:5", "mirror": True}),
    (["--rotate", "yaw:30"], {"rotate": "yaw:30"}),
    (
        ["--method", "montecarlo", "--sampler", "importance", "--samples", "4096", "--seed", "7"],
        {"method": "montecarlo", "sampler": "importance", "samples": 4096, "seed": 7},
    ),
    (["--method", "montecarlo", "--samples", "2048"], {"method": "montecarlo", "samples": 2048}),
]


def project_quietly(source, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return shlight.project(source, **options)


@pytest.mark.parametrize("flags,options", OPTION_SETS, ids=lambda v: " ".join(v) if isinstance(v, list) else None)
def test_coefficient_files_equal_the_clis_byte_for_byte(cli, tmp_path, flags, options):
    for m in MAPS:
        want = tmp_path / f"{m.stem}-cli.json"
        code, _, err = run_cli(cli, "project", m, *flags, "-o", want)
        assert code == 0, err
        sh = project_quietly(str(m), **options)
        got = tmp_path / f"{m.stem}-py.json"
        sh.save(got)
        assert got.read_bytes() == want.read_bytes(), (m, flags)
        back = shlight.load(want)
        assert np.array_equal(back.coefficients, sh.coefficients)
        if "method" in options:
            assert np.array_equal(back.std_error, sh.std_error)
            assert (sh.std_error > 0).all()
        else:
            assert sh.std_error is None


def test_every_export_equals_the_clis_format_output(cli, tmp_path):
    m = MAPS[0]
    sh = project_quietly(str(m), lmax=2)
    assert len(shlight.EXPORT_FORMATS) == 10
    for fmt in shlight.EXPORT_FORMATS:
        if fmt == "gltf":
            # From a map the CLI's light carries specular images; from
            # coefficients alone a glTF light is refused.
            with pytest.raises(shlight.ShlightError, match="specularImages"):
                sh.export("gltf")
            continue
        out = tmp_path / f"probe.{fmt}"
        code, _, err = run_cli(cli, "project", m, "--format", fmt, "-o", out)
        assert code == 0, err
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            text = sh.export(fmt)
        assert text == out.read_text(), fmt
    with pytest.raises(shlight.ShlightError, match="unity"):
        sh.export("unreal")


def test_the_bundled_maps_are_distinct():
    contents = [m.read_bytes() for m in MAPS]
    assert len(MAPS) == 4 and len(set(contents)) == len(contents), MAPS
