"""shlight.project and project_many read a large map by rows: an
8192x4096 map (402 MB as float texels) projects in a process whose peak
resident memory stays a small fraction of that, as `shlight project` does
(docs/limits.md, "Reading by rows"), while the in-memory route holds the
whole map."""

import json
import subprocess
import sys

import numpy as np

from conftest import run_cli

W, H = 8192, 4096


def write_flat_hdr(path):
    """A Radiance RGBE map written flat (no run-length coding), with
    values varying along both axes."""
    x = np.arange(W, dtype=np.uint32)[None, :]
    y = np.arange(H, dtype=np.uint32)[:, None]
    rgbe = np.empty((H, W, 4), np.uint8)
    rgbe[..., 0] = x * 7 % 200 + 20
    rgbe[..., 1] = y * 3 % 200 + 20
    rgbe[..., 2] = (x // 64 + y // 64) % 2 * 100 + 60
    rgbe[..., 3] = 129
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (H, W))
        f.write(rgbe.tobytes())


def peak_mb(code):
    """Runs `code` in a fresh interpreter; returns that process's peak
    resident memory in MB (its VmHWM: getrusage's maxrss would carry the
    peak of the test process it was forked from across the exec)."""
    script = (
        "import json, shlight\n"
        + code
        + "\nprint([l for l in open('/proc/self/status') if l.startswith('VmHWM')][0].split()[1])"
    )
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return int(r.stdout.split()[-1]) / 1024


def test_large_maps_project_by_rows_in_bounded_memory(cli, tmp_path):
    hdr = tmp_path / "large.hdr"
    write_flat_hdr(hdr)
    texels_mb = W * H * 12 / 2**20
    one = tmp_path / "one.json"
    streamed = peak_mb(
        f"sh = shlight.project({str(hdr)!r}, 8)\n"
        f"open({str(one)!r}, 'w').write(sh.to_json())"
    )
    many_out = tmp_path / "many.json"
    many = peak_mb(
        f"shs = shlight.project_many([{str(hdr)!r}] * 2, 8)\n"
        f"open({str(many_out)!r}, 'w').write(json.dumps([s.to_json() for s in shs]))"
    )
    whole = peak_mb(
        f"shlight.project({str(hdr)!r}, 8, method='montecarlo', samples=1024)"
    )
    # The in-memory route holds the texels; reading by rows does not, in
    # one call or in two workers at once.
    assert whole > 0.9 * texels_mb, (whole, texels_mb)
    assert streamed < 0.3 * texels_mb, (streamed, texels_mb)
    assert many < 0.3 * texels_mb, (many, texels_mb)
    print(f"peak resident memory: {streamed:.0f} MB by rows, {many:.0f} MB for project_many, {whole:.0f} MB in memory")
    # The same coefficients as the CLI's (which reads by rows too) and as
    # each project_many worker's.
    cli_out = tmp_path / "cli.json"
    code, _, err = run_cli(cli, "project", hdr, "--lmax", "8", "-o", cli_out)
    assert code == 0, err
    want = np.array(json.loads(cli_out.read_text())["coefficients"])
    got = np.array(json.loads(one.read_text())["coefficients"])
    assert np.array_equal(got, want)
    for text in json.loads(many_out.read_text()):
        assert np.array_equal(np.array(json.loads(text)["coefficients"]), want)
