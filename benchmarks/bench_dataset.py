"""Datasets: throughput over pybullet's random_urdfs, scaling and the cost of Dask.

Four runs of the same job (three hard fingers, mu 0.5, regions grown on the
mesh around the best sampled prototype) over the same objects, in one
process each time:

* baseline: the loop a user would write, ``synthesize(load_object(p))`` for
  each file and each grasp's record (with its certificate) kept in a list;
* ``run_dataset`` with one worker (in this process): the cost of records,
  atomic writes and the Parquet table;
* ``run_dataset`` on a local pool of two processes: the scaling;
* ``run_dataset`` on a Dask ``LocalCluster`` of two single-thread worker
  processes (``NUMBA_NUM_THREADS=1``, like the pool's workers): the
  overhead of Dask against the local pool.

    uv run --extra test python benchmarks/bench_dataset.py [--objects 1000] [--samples 2000]
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

import pybullet_data
from _tables import parse, table

from forceclosure.datasets import Job, run_dataset
from forceclosure.errors import InputError
from forceclosure.objects.io import load_object
from forceclosure.synthesis.best import synthesize


def _quiet(line: str) -> None:
    """The failures (non-manifold meshes, a NaN vertex) are counted, not printed."""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--objects", type=int, default=1000)
    ap.add_argument("--samples", type=int, default=2000)
    args = parse(ap)
    urdfs = Path(pybullet_data.getDataPath()) / "random_urdfs"
    paths = [urdfs / f"{i:03d}" / f"{i:03d}.urdf" for i in range(args.objects)]
    job = Job(fingers=3, contact="hard", mu=0.5, top=1, samples=args.samples)
    print(f"{len(paths)} random_urdfs objects; job: 3 hard fingers, mu 0.5, "
          f"{args.samples} samples, best grasp and its regions")
    synthesize(load_object(paths[0]), 3, "hard", 0.5, top=1, samples=args.samples)  # warm up
    start = time.perf_counter()
    kept, failed = [], 0
    for p in paths:
        try:
            found = synthesize(load_object(p), 3, "hard", 0.5, top=1,
                               samples=args.samples).found
        except InputError:  # e.g. a non-manifold mesh
            failed += 1
            continue
        kept.append([r.to_dict() for r in found])
    base = time.perf_counter() - start
    print(f"  baseline loop, 1 process:        {base:7.1f} s  {len(paths) / base:6.2f} obj/s  "
          f"({len(kept)} done, {failed} failed)")
    rates = {}
    rows = [["baseline: a plain loop, `synthesize` + `to_dict` per object", f"{base:.1f}",
             f"{len(paths) / base:.2f}", f"{len(kept)} done, {failed} failed"]]
    scratch = Path(tempfile.mkdtemp())
    try:
        for label, kwargs in (("run_dataset, 1 worker", {"workers": 1}),
                              ("run_dataset, local pool of 2", {"workers": 2})):
            s = run_dataset(paths, scratch / label, job, progress=False, log=_quiet, **kwargs)
            rates[label] = s.throughput
            rows.append([f"`{label}`", f"{s.seconds:.1f}", f"{s.throughput:.2f}",
                         f"{s.done} done, {s.failed} failed"])
            print(f"  {label + ':':32s} {s.seconds:7.1f} s  {s.throughput:6.2f} obj/s  "
                  f"({s.done} done, {s.failed} failed)")
        from distributed import Client, LocalCluster

        start = time.perf_counter()
        # one kernel thread per worker, as the local pool does
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None, env={"NUMBA_NUM_THREADS": "1"}
                          ) as cluster, Client(cluster) as client:
            startup = time.perf_counter() - start
            s = run_dataset(paths, scratch / "dask", job, executor=client.get_executor(),
                            workers=2, progress=False, log=_quiet)
        rates["dask"] = s.throughput
        rows.append(["`run_dataset`, Dask `LocalCluster` of 2", f"{s.seconds:.1f}",
                     f"{s.throughput:.2f}", f"{s.done} done, {s.failed} failed; "
                     f"cluster start {startup:.1f} s more"])
        print(f"  {'Dask LocalCluster of 2:':32s} {s.seconds:7.1f} s  {s.throughput:6.2f} obj/s"
              f"  ({s.done} done, {s.failed} failed; cluster start {startup:.1f} s more)")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    table("dataset", ["run", "seconds (wall)", "objects/s", "objects"], rows)
    one = rates["run_dataset, 1 worker"]
    pool = rates["run_dataset, local pool of 2"]
    print(f"  records and table cost {100 * (1 - one * base / len(paths)):+.1f} % against "
          f"the baseline loop; 2 workers scale {pool / one:.2f}x; Dask runs at "
          f"{rates['dask'] / pool:.2f}x the local pool's throughput")


if __name__ == "__main__":
    main()
