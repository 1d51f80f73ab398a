"""Project a folder of environment maps to SH coefficients on a Dask cluster.

One task per map: each worker reads and projects its maps with shlight (in
Rust, all of the worker's cores), and the coefficients come back to this
process, which writes one ``.npz``:

- ``coefficients``: float64 ``(N, (lmax+1)**2, 3)``, map ``i`` in row ``i``
  (real orthonormal SH, Condon-Shortley phase, index ``l*(l+1)+m``);
- ``files``: the ``N`` map paths, as found, sorted;
- ``lmax``, ``frame``, ``quantity``: what the coefficients are.

On this machine (a local cluster of worker processes)::

    python dask_dataset.py envmaps/ coeffs.npz --workers 2 --lmax 4

On a real cluster, start a scheduler and workers that can read the folder
(a shared file system or object store mount) and have shlight installed
(``pip install ./python``), then give the scheduler's address::

    dask scheduler                                   # on one node
    dask worker tcp://SCHEDULER:8786 --nthreads 1    # on every node
    python dask_dataset.py /data/hdris coeffs.npz --scheduler tcp://SCHEDULER:8786

The paths are opened by the workers, so they must mean the same files there.
Results equal ``shlight.project_many`` on the same files bit for bit.
"""

import argparse
import glob
import os
import sys

import numpy as np


def project_file(path, lmax, options):
    """The task: one map's coefficients (runs on a worker)."""
    import warnings

    import shlight

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return shlight.project(path, lmax, **options).coefficients


def find_maps(folder, pattern):
    """The maps of ``folder`` matching ``pattern``, sorted."""
    return sorted(glob.glob(os.path.join(folder, pattern)))


def project_folder(client, folder, out, lmax=2, pattern="*.exr", **options):
    """Projects every map of ``folder`` on ``client``'s cluster, one task
    per map, and writes ``out`` (.npz). Returns the file list."""
    files = find_maps(folder, pattern)
    if not files:
        raise SystemExit(f"{folder}: no maps match {pattern}")
    futures = client.map(project_file, files, lmax=lmax, options=options, pure=False)
    coefficients = np.stack(client.gather(futures))
    frame = "z-up" if options.get("up") == "z" else "y-up"
    np.savez(
        out,
        coefficients=coefficients,
        files=np.array(files),
        lmax=lmax,
        frame=frame,
        quantity=options.get("quantity", "radiance"),
    )
    return files


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("folder")
    p.add_argument("out", help="the .npz to write")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of a running scheduler (tcp://HOST:8786)")
    where.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    p.add_argument("--lmax", type=int, default=2)
    p.add_argument("--pattern", default="*.exr")
    p.add_argument("--up", default="y", choices=["y", "z"])
    p.add_argument("--quantity", default="radiance", choices=["radiance", "irradiance"])
    args = p.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    options = {"up": args.up, "quantity": args.quantity}
    if args.scheduler:
        with Client(args.scheduler) as client:
            files = project_folder(client, args.folder, args.out, args.lmax, args.pattern, **options)
    else:
        with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True) as cluster, Client(cluster) as client:
            files = project_folder(client, args.folder, args.out, args.lmax, args.pattern, **options)
    print(f"{len(files)} maps -> {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
