"""Fixtures of the shlight Python tests: the repository's bundled maps and
the shlight command line built from the same sources (the reference every
number is compared with)."""

import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
ENVMAPS = ROOT / "envmaps"
# The distinct bundled maps: default.exr is a byte-for-byte copy of park.exr
# (envmaps/README.md), so it would only run park twice.
MAPS = sorted(p for p in ENVMAPS.glob("*.exr") if p.name != "default.exr")


def _target_dir():
    return pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))


@pytest.fixture(scope="session")
def cli():
    """Path of the `shlight` binary: $SHLIGHT_CLI, else the workspace's
    release build (built here with `cargo build --release` when missing)."""
    given = os.environ.get("SHLIGHT_CLI")
    if given:
        return given
    binary = _target_dir() / "release" / "shlight"
    if not binary.exists():
        cargo = shutil.which("cargo")
        assert cargo, "the tests compare with the shlight CLI; cargo is needed to build it"
        subprocess.run(
            [cargo, "build", "--release", "--bin", "shlight"], cwd=ROOT, check=True
        )
    return str(binary)


def run_cli(cli, *args, cwd=None):
    """Runs the CLI; returns (returncode, stdout, stderr)."""
    r = subprocess.run(
        [cli, *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
    )
    return r.returncode, r.stdout, r.stderr


def cli_error(stderr):
    """The message of the CLI's `error: ...` line."""
    lines = [l for l in stderr.splitlines() if l.startswith("error: ")]
    assert lines, f"no error line in {stderr!r}"
    return lines[-1][len("error: "):]
