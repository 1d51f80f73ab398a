"""The Python package against its peers (figures in docs/benchmarks.md).

1. Overhead: shlight.project on a 2048x1024 float32 array at lmax 2 against
   the same projection in Rust alone (crates/shlight-pipeline/examples/
   time_projection.rs on the same texels), medians of the same run.
2. 64 maps (the bundled 512x256 maps, cycled): maps per second of
   shlight.project_many on every core, of the CLI batch
   (`shlight project a b c ... -o DIR`), and of a numpy projection written
   the obvious way (python/tests/reference.py, one map after another).
3. The same 64 maps through python/examples/dask_dataset.py on a
   LocalCluster of 2 worker processes (cluster start-up timed apart).

Run from the repository root after `pip install ./python` and
`cargo build --release` (CARGO_TARGET_DIR honoured):

    python benches/python_peers.py [--runs 7]
"""

import argparse
import os
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np

import shlight

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python" / "tests"))
sys.path.insert(0, str(ROOT / "python" / "examples"))
from reference import project_l2  # noqa: E402

TARGET = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
MAPS = sorted((ROOT / "envmaps").glob("*.exr"))


def median_time(f, runs):
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return statistics.median(times), times


def overhead(runs, tmp):
    small = shlight.read_image(MAPS[2])
    big = np.ascontiguousarray(np.repeat(np.repeat(small, 4, axis=0), 4, axis=1))
    assert big.shape == (1024, 2048, 3) and big.dtype == np.float32
    path = tmp / "big.exr"
    shlight.write_image(path, big)
    assert np.array_equal(shlight.read_image(path), big)
    example = TARGET / "release" / "examples" / "time_projection"
    if not example.exists():
        subprocess.run(
            ["cargo", "build", "--release", "-p", "shlight-pipeline", "--example", "time_projection"],
            cwd=ROOT,
            check=True,
        )
    rust = []
    py = []
    # Interleaved rounds, so that both see the same machine load.
    for _ in range(3):
        out = subprocess.run([str(example), str(path), "2", str(runs)], capture_output=True, text=True, check=True)
        rust.append(float(out.stdout))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            py.append(median_time(lambda: shlight.project(big, 2), runs)[0])
    r, p = statistics.median(rust), statistics.median(py)
    print(f"overhead 2048x1024 lmax 2: Rust {r * 1e3:.2f} ms, Python {p * 1e3:.2f} ms, "
          f"ratio {p / r:.3f} (rounds: rust {[f'{v*1e3:.2f}' for v in rust]}, python {[f'{v*1e3:.2f}' for v in py]})")


def batch(runs, tmp):
    folder = tmp / "maps"
    folder.mkdir()
    paths = []
    for k in range(64):
        m = MAPS[k % len(MAPS)]
        p = folder / f"{k:02d}-{m.name}"
        shutil.copy(m, p)
        paths.append(str(p))
    cli = TARGET / "release" / "shlight"
    out = tmp / "out"
    out.mkdir()

    def many():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            shlight.project_many(paths, 2)

    def cli_batch():
        subprocess.run([str(cli), "--quiet", "project", *paths, "-o", str(out)], check=True)

    def numpy_loop():
        for p in paths:
            project_l2(shlight.read_image(p))

    rows = []
    for name, f in [("project_many", many), ("CLI batch", cli_batch), ("numpy loop", numpy_loop)]:
        m, _ = median_time(f, runs if name != "numpy loop" else max(3, runs // 2))
        rows.append((name, m))
    base = rows[1][1]
    for name, m in rows:
        print(f"64 maps 512x256 lmax 2, {name}: {m:.3f} s, {64 / m:.0f} maps/s, {m / base:.2f}x the CLI batch's time")

    import dask_dataset
    from dask.distributed import Client, LocalCluster

    t = time.perf_counter()
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster, Client(cluster) as client:
        start = time.perf_counter() - t
        m, _ = median_time(lambda: dask_dataset.project_folder(client, str(folder), str(tmp / "c.npz"), 2), runs)
    print(f"64 maps on dask LocalCluster(2 worker processes): start-up {start:.2f} s, "
          f"{m:.3f} s per run, {64 / m:.0f} maps/s, {m / 64 * 1e3:.1f} ms per map")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--runs", type=int, default=7)
    args = p.parse_args()
    print(f"cores: {os.cpu_count()}")
    with tempfile.TemporaryDirectory() as d:
        tmp = pathlib.Path(d)
        overhead(args.runs, tmp)
        batch(args.runs, tmp)


if __name__ == "__main__":
    main()
