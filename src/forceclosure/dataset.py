"""Datasets: one job over thousands of objects, resumable, on any executor.

``forceclosure dataset INPUT... --out DIR`` (and :func:`run_dataset`) runs
one job on every object of a set: the synthesis of ``forceclosure
synthesize`` (the best grasps and their independent regions, §5), or the
analysis of grasps given per object (Theorem 1, with epsilon and a check
that the contacts lie on the object). The objects are spread over an
executor: a local process pool over all cores by default, or any
``concurrent.futures.Executor``, a Dask cluster's included
(``Client.get_executor()``).

Nothing is lost and nothing is done twice. ``DIR`` holds

* ``job.json``: the job; re-running in the same ``DIR`` must ask for the
  same job, and then resumes;
* ``objects/<name>-<hash>.json``: one record per object, written
  atomically (a temporary file renamed) by the driver as soon as the
  object finishes, whatever worker computed it; objects with a record are
  skipped on a re-run (failed ones too, unless ``retry_failed``);
* ``results.parquet``: one row per object (status, timings, best grasps
  and region sizes), rebuilt from the records at the end of every run,
  also an interrupted one.

A bad or unreadable object is recorded as ``failed`` with its one-line
error; an object over the time limit as ``timeout``. A worker that dies
(killed, out of memory) costs only the objects it was running: on a local
pool they are retried on a fresh pool, on Dask the scheduler retries them;
an object that kills workers three times is recorded as ``failed``.
"""

from __future__ import annotations

import ctypes
import glob
import hashlib
import json
import multiprocessing
import os
import re
import signal
import socket
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import Executor, Future, ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager, suppress
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError
from .objects.io import MESH_SUFFIXES, POLYGON_SUFFIXES, ROBOT_SUFFIXES
from .objects.urdf import mesh_files

#: Files a folder contributes: polygons, meshes, robot descriptions.
OBJECT_SUFFIXES = POLYGON_SUFFIXES + MESH_SUFFIXES + ROBOT_SUFFIXES
#: Grasp files given per object (analysis mode), not objects themselves.
GRASP_SUFFIXES = (".grasps.json", ".grasps.npz")
#: A worker may die this many times on one object before it is recorded as failed.
MAX_CRASHES = 3
#: Contacts farther than this (relative to the object's size) are off its surface.
SURFACE_RTOL = 1e-3
STATUSES = ("done", "failed", "timeout")


@dataclass(frozen=True)
class Job:
    """What to do with every object.

    Attributes
    ----------
    mode : {"synthesize", "analyze"}
        Find the best grasps and their regions (the options below, as for
        ``forceclosure synthesize``), or analyse the grasps given for each
        object in a grasp file (``grasps``).
    fingers : int or None
        None: the fewest that hold the object (2 on polygons; on polyhedra 2
        soft, 3 hard, 7 frictionless).
    contact, mu, top, margin, construction, method, samples, seed
        As for :func:`forceclosure.synthesis.best.synthesize`.
    grasps : str
        Analysis: where each object's grasp file is, with ``{dir}`` (the
        object's folder), ``{stem}`` and ``{name}`` filled in; ``.npz`` or
        JSON grasp files. Default: ``{dir}/{stem}.grasps.npz``, else
        ``{dir}/{stem}.grasps.json``.
    timeout : float or None
        Seconds one object may take; None for no limit.
    allow_open : bool
        Accept open and non-manifold meshes (``load_object(..., allow_open=True)``);
        part of the job's identity, since it changes which objects load and how.
    """

    mode: str = "synthesize"
    fingers: int | None = None
    contact: str = "hard"
    mu: float = 0.3
    top: int = 5
    margin: float = 1e-3
    construction: str = "maximal"
    method: str = "auto"
    samples: int = 20_000
    seed: int = 0
    grasps: str = ""
    timeout: float | None = None
    allow_open: bool = False

    def __post_init__(self) -> None:
        if self.mode not in ("synthesize", "analyze"):
            raise InputError(f"mode must be synthesize or analyze, got {self.mode!r}")
        if self.timeout is not None and not self.timeout > 0:
            raise InputError(f"--timeout must be a positive number of seconds, got "
                             f"{self.timeout:g}")
        if self.samples < 1:
            raise InputError(f"--samples must be at least 1, got {self.samples}")
        if self.fingers is not None and self.fingers < 1:
            raise InputError(f"--fingers must be at least 1, got {self.fingers}")
        try:
            self.grasps.format(dir="", stem="", name="")
        except (KeyError, IndexError, ValueError) as e:
            raise InputError(f"--grasps {self.grasps}: {{dir}}, {{stem}} and {{name}} are "
                             f"the placeholders it may use ({type(e).__name__}: {e})") from None

    def identity(self) -> dict[str, Any]:
        """The options that decide the results (the time limit does not)."""
        if self.mode == "analyze":
            return {"mode": "analyze", "grasps": self.grasps, "allow_open": self.allow_open}
        record = asdict(self)
        record.pop("timeout")
        return record


@dataclass(frozen=True)
class Summary:
    """What a run did.

    Attributes
    ----------
    objects : int
        Objects in the input set.
    done, failed, timeout : int
        Objects with each status in ``DIR`` after the run.
    computed : int
        Objects computed by this run (the others were skipped: done before).
    skipped : int
    seconds : float
        Wall time of this run.
    workers : int
    out : Path
    """

    objects: int
    done: int
    failed: int
    timeout: int
    computed: int
    skipped: int
    seconds: float
    workers: int
    out: Path
    interrupted: bool = False

    @property
    def throughput(self) -> float:
        """Objects computed per second of this run."""
        return self.computed / self.seconds if self.seconds > 0 else 0.0

    def to_dict(self) -> dict[str, Any]:
        return {**{f.name: getattr(self, f.name) for f in fields(self)},
                "out": str(self.out), "objects_per_second": round(self.throughput, 4)}

    def __str__(self) -> str:
        lines = [f"{self.objects} objects: {self.done} done, {self.failed} failed, "
                 f"{self.timeout} over the time limit; {self.skipped} skipped (done before)"]
        if self.computed:
            lines.append(f"computed {self.computed} in {self.seconds:.1f} s "
                         f"({self.throughput:.3g} objects/s on {self.workers} "
                         f"worker{'s' if self.workers != 1 else ''})")
        lines.append(f"results: {self.out / 'results.parquet'} (one row per object), "
                     f"{self.out / 'objects'} (full records)")
        if self.interrupted:
            lines.append("interrupted: run the same command again to resume")
        return "\n".join(lines)


# -- the input set --------------------------------------------------------------------------

def expand_inputs(inputs: Iterable[str | Path]) -> list[Path]:
    """Object files from files, folders (searched recursively) and glob patterns.

    A folder contributes its polygon, mesh and URDF files, but not the mesh
    files its URDFs name (the URDF stands for them, with its scale) nor
    grasp files (``*.grasps.json``). A file named directly is always taken.

    Examples
    --------
    >>> import pybullet_data, os
    >>> urdfs = os.path.join(pybullet_data.getDataPath(), "random_urdfs")
    >>> found = expand_inputs([urdfs])
    >>> len(found), found[0].name
    (1000, '000.urdf')
    """
    from .objects import POLYGONS, POLYHEDRA

    named: list[Path] = []
    walked: list[Path] = []
    for item in inputs:
        path = Path(item)
        if path.is_file() or (not path.exists() and str(item) in {*POLYGONS, *POLYHEDRA}):
            named.append(path)  # a file, or a bundled object's name
        elif path.is_dir():
            walked += [p for p in sorted(path.rglob("*"))
                       if p.is_file() and p.suffix.lower() in OBJECT_SUFFIXES
                       and not p.name.lower().endswith(GRASP_SUFFIXES)]
        else:
            matches = sorted(Path(m) for m in glob.glob(str(item), recursive=True))
            matches = [m for m in matches if m.is_file()]
            if not matches:
                raise InputError(f"{item}: no such file or folder, and no files match it")
            named += matches
    meshes_of_urdfs = set()
    for p in walked:
        if p.suffix.lower() in ROBOT_SUFFIXES:
            with suppress(InputError):  # a bad URDF is recorded as failed in its turn
                meshes_of_urdfs.update(m.resolve() for m in mesh_files(p))
    walked = [p for p in walked if p.resolve() not in meshes_of_urdfs]
    unique: dict[str, Path] = {}
    for p in named + walked:
        unique.setdefault(_key(p), p)
    return sorted(unique.values(), key=lambda p: str(p))


def _key(path: Path) -> str:
    """What identifies an object: its absolute path (a bundled object: its name)."""
    return str(path.resolve()) if path.exists() else str(path)


def record_name(path: Path) -> str:
    """The file name of an object's record: readable, and unique per object."""
    key = _key(path)
    stem = re.sub(r"[^A-Za-z0-9._-]+", "_", path.name)[:60]
    return f"{stem}-{hashlib.sha1(key.encode()).hexdigest()[:12]}.json"


# -- one object (runs on a worker) ----------------------------------------------------------

class ObjectTimeout(BaseException):
    """An object ran over its time limit. A ``BaseException``, like ``KeyboardInterrupt``,
    so that no ``except Exception`` on the way (in a file reader, say) swallows it."""


@contextmanager
def deadline(seconds: float | None) -> Iterator[None]:
    """Raise :class:`ObjectTimeout` in this thread after ``seconds``.

    The main thread (a process-pool worker) uses ``SIGALRM``; another thread
    (a Dask worker's) gets the exception raised in it asynchronously. Either
    way it arrives between Python bytecodes, so one long call into compiled
    code (a hull of a huge mesh) finishes first.
    """
    if seconds is None:
        yield
        return
    if threading.current_thread() is threading.main_thread():
        def alarm(signum, frame):
            raise ObjectTimeout

        previous = signal.signal(signal.SIGALRM, alarm)
        outer, _ = signal.setitimer(signal.ITIMER_REAL, seconds)
        start = time.monotonic()
        try:
            yield
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
            if outer > 0:  # an alarm set around ours (a test runner's time limit) goes on
                signal.setitimer(signal.ITIMER_REAL,
                                 max(outer - (time.monotonic() - start), 1e-3))
        return
    ident, lock, armed = threading.get_ident(), threading.Lock(), [True]

    def fire() -> None:
        with lock:
            if armed[0]:
                ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(ident),
                                                           ctypes.py_object(ObjectTimeout))

    timer = threading.Timer(seconds, fire)
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        with lock:
            armed[0] = False
        timer.cancel()
        # an exception set but not yet raised must not escape the block
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(ident), None)


def _describe(obj) -> dict[str, Any]:
    if obj.dim == 2:
        return {"kind": "polygon", "size": obj.size, "edges": len(obj.edges),
                "triangles": 0}
    return {"kind": "polyhedron", "size": obj.size, "faces": len(obj.faces),
            "triangles": len(obj.triangles)}


def _synthesize(obj, job: Job) -> dict[str, Any]:
    from .synthesis.best import synthesize

    result = synthesize(obj, job.fingers, job.contact, job.mu, top=job.top, margin=job.margin,
                        construction=job.construction, method=job.method,
                        samples=job.samples, seed=job.seed)
    grasps = [r.to_dict() for r in result.found]
    return {"fingers": result.fingers, "contact": result.contact, "mu": result.mu,
            "method": result.method, "grasps": grasps}


def grasp_file_of(path: Path, pattern: str) -> Path:
    """The grasp file given for the object at ``path`` (analysis mode)."""
    fill = {"dir": str(path.parent), "stem": path.stem, "name": path.name}
    if pattern:
        return Path(pattern.format(**fill))
    for suffix in GRASP_SUFFIXES[::-1]:  # .npz first
        candidate = path.parent / f"{path.stem}{suffix}"
        if candidate.exists():
            return candidate
    raise InputError(f"{path.name}: no grasp file {path.stem}.grasps.npz or "
                     f"{path.stem}.grasps.json beside it (or give --grasps PATTERN)")


def surface_distance(obj, points: np.ndarray) -> np.ndarray:
    """Distance of each point to the object's boundary."""
    if obj.dim == 2:
        import shapely

        return shapely.distance(obj.to_shapely().boundary, shapely.points(points))
    return np.array([obj.locate(p)[2] for p in points])


def _analyze(obj, path: Path, job: Job) -> dict[str, Any]:
    from .grasp_arrays import analyze_npz, iter_chunks, open_npz
    from .grasp_file import parse_grasp_file, result_record

    source = grasp_file_of(path, job.grasps)
    if not source.is_file():
        raise InputError(f"{path.name}: no grasp file {source}")
    if source.suffix.lower() == ".npz":
        info = open_npz(str(source))
        if info.dim != obj.dim:
            raise InputError(f"{source.name}: {info.dim}-D grasps for a {obj.dim}-D object")
        results = analyze_npz(str(source), epsilon=True)
        points = np.concatenate([c["points"].reshape(-1, obj.dim) for c in iter_chunks(info)])
        counts = results.counts()
        closed = results.epsilon[results.code == 2]
        verdicts = results.code.tolist()
        errors = results.errors
        eps_median = float(np.median(closed)) if len(closed) else None
        per_grasp: list[Any] = []
    else:
        grasp_file = parse_grasp_file(source.read_text(encoding="utf-8"), source.name)
        per_grasp = [result_record(entry, grasp_file.cone)[0] for entry in grasp_file.grasps]
        names = {"closure": 2, "marginal": 1, "none": 0}
        verdicts = [names.get(r.get("verdict"), -1) for r in per_grasp]
        counts = {k: verdicts.count(c) for k, c in (("closure", 2), ("marginal", 1),
                                                      ("none", 0), ("errors", -1))}
        errors = [r["error"] for r in per_grasp if "error" in r]
        eps = [r["epsilon"] for r in per_grasp if r.get("verdict") == "closure"
               and r.get("epsilon") is not None]
        eps_median = float(np.median(eps)) if eps else None
        good = [e for e in grasp_file.grasps if e.error is None]
        for e in good:
            if any(len(c.point) != obj.dim for c in e.contacts):
                raise InputError(f"{source.name}: {e.label}: "
                                 f"{len(e.contacts[0].point)}-D contacts for a {obj.dim}-D "
                                 "object")
        points = np.array([c.point for e in good for c in e.contacts]).reshape(-1, obj.dim)
    finite = points[np.all(np.isfinite(points), axis=1)]
    off = int(np.sum(surface_distance(obj, finite) > SURFACE_RTOL * obj.size)) if len(
        finite) else 0
    return {"grasp_file": str(source), "grasps": len(verdicts), **counts,
            "epsilon_median": eps_median, "off_surface": off, "verdicts": verdicts,
            "grasp_errors": errors, "results": per_grasp}


def process_object(path: str | Path, job: Job) -> dict[str, Any]:
    """Run the job on one object and return its record; never raises for a bad object.

    Examples
    --------
    >>> record = process_object("cube", Job(contact="soft", mu=0.5, top=1))
    >>> record["status"], len(record["grasps"])
    ('done', 1)
    >>> process_object("nowhere.stl", Job())["error"]
    "nowhere.stl: no such file, and no bundled object of that name (see 'forceclosure objects')"
    """
    from .objects.io import load_object

    path = Path(path)
    record: dict[str, Any] = {"path": _key(path), "name": path.stem, "status": "done",
                              "error": None, "worker": f"{socket.gethostname()}:{os.getpid()}"}
    start = time.perf_counter()
    try:
        with deadline(job.timeout):
            obj = load_object(path, allow_open=job.allow_open)
            record.update(_describe(obj))
            record["load_seconds"] = time.perf_counter() - start
            record.update(_synthesize(obj, job) if job.mode == "synthesize"
                          else _analyze(obj, path, job))
    except InputError as e:
        record.update(status="failed", error=str(e))
    except ObjectTimeout:
        record.update(status="timeout", error=f"{path.name}: over the time limit of "
                                              f"{job.timeout:g} s")
    except MemoryError:
        record.update(status="failed", error=f"{path.name}: out of memory")
    except Exception as e:  # an internal error: one line, and the run goes on
        first = str(e).splitlines()[0] if str(e) else ""
        record.update(status="failed", error=f"{path.name}: internal error: "
                                             f"{type(e).__name__}: {first}")
    record["seconds"] = time.perf_counter() - start
    return record


# -- the driver -----------------------------------------------------------------------------

def _write_atomically(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def _read_records(folder: Path) -> dict[str, dict[str, Any]]:
    records = {}
    for f in folder.glob("*.json"):
        try:
            records[f.name] = json.loads(f.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue  # cannot happen with atomic writes; such a file is redone
    return records


def _check_job(out: Path, job: Job) -> None:
    path = out / "job.json"
    wanted = job.identity()
    if path.exists():
        try:
            held = json.loads(path.read_text(encoding="utf-8"))
        except ValueError:
            raise InputError(f"{path}: not a job file; use another --out") from None
        if isinstance(held, dict):
            held.setdefault("allow_open", False)  # written before the option existed
        if held != wanted:
            diff = [k for k in sorted(set(held) | set(wanted)) if held.get(k) != wanted.get(k)]
            what = ", ".join(f"{k} {held.get(k)!r} there, {wanted.get(k)!r} here"
                             for k in diff[:3])
            raise InputError(f"{out} holds results of another job ({what}); use another "
                             "--out, or the same options to resume")
    else:
        _write_atomically(path, json.dumps(wanted, indent=2) + "\n")


#: The columns of results.parquet, in order: (name, pyarrow type name).
COLUMNS = (("name", "string"), ("path", "string"), ("status", "string"), ("error", "string"),
           ("seconds", "float64"), ("load_seconds", "float64"), ("worker", "string"),
           ("kind", "string"), ("size", "float64"), ("faces", "int64"), ("edges", "int64"),
           ("triangles", "int64"),
           # synthesis
           ("fingers", "int64"), ("contact", "string"), ("mu", "float64"),
           ("method", "string"), ("grasps", "int64"), ("best_min_region", "float64"),
           ("best_relative_min_region", "float64"), ("best_region_sizes", "list<float64>"),
           ("best_faces", "string"), ("all_certified", "bool"),
           # analysis
           ("closure", "int64"), ("marginal", "int64"), ("none", "int64"),
           ("errors", "int64"), ("epsilon_median", "float64"), ("off_surface", "int64"))


def row_of(record: dict[str, Any]) -> dict[str, Any]:
    """The results.parquet row of an object's record: scalars, and the best grasp's sizes
    (areas on polyhedra, lengths on polygons)."""
    row = {name: record.get(name) for name, _ in COLUMNS}
    grasps = record.get("grasps")
    if isinstance(grasps, list):  # synthesis
        row["grasps"] = len(grasps)
        if grasps:
            best = grasps[0]
            spatial = "min_area" in best
            row["best_min_region"] = best["min_area" if spatial else "min_length"]
            row["best_relative_min_region"] = best["relative_min_area" if spatial
                                                   else "relative_min_length"]
            row["best_region_sizes"] = best["areas" if spatial else "lengths"]
            row["best_faces"] = json.dumps(best["faces" if spatial else "edges"])
        row["all_certified"] = all(g["certificate"]["holds"] for g in grasps)
    return row


def write_table(out: Path, records: Iterable[dict[str, Any]]) -> Path:
    """Write ``out/results.parquet`` (atomically) from object records."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    types = {"string": pa.string(), "float64": pa.float64(), "int64": pa.int64(),
             "bool": pa.bool_(), "list<float64>": pa.list_(pa.float64())}
    schema = pa.schema([(name, types[t]) for name, t in COLUMNS])
    rows = sorted((row_of(r) for r in records), key=lambda r: (r["path"] or ""))
    table = pa.Table.from_pylist(rows, schema=schema)
    path = out / "results.parquet"
    tmp = out / f".results.parquet.{os.getpid()}.tmp"
    pq.write_table(table, tmp)
    os.replace(tmp, path)
    return path


@dataclass
class _Run:
    """The driver's state: the objects still to do, and how often each killed its worker."""

    todo: dict[str, Path]
    crashes: dict[str, int] = field(default_factory=dict)


def run_dataset(inputs: Sequence[str | Path], out: str | Path, job: Job = Job(), *,
                executor: Executor | None = None, workers: int | None = None,
                retry_failed: bool = False, progress: bool | None = None,
                log: Callable[[str], object] | None = None) -> Summary:
    """Run ``job`` on every object of ``inputs``, writing results to ``out``; resumable.

    Parameters
    ----------
    inputs : sequence of str or Path
        Files, folders and glob patterns (:func:`expand_inputs`).
    out : str or Path
        The results folder (created). Re-running with the same job resumes.
    job : Job
    executor : concurrent.futures.Executor, optional
        Where the objects are computed, e.g. a Dask ``Client.get_executor()``.
        Its workers must see the input files at the same paths. Default: a
        local process pool of ``workers`` processes (all cores); with
        ``workers=1`` everything runs in this process.
    retry_failed : bool
        Compute failed and timed-out objects again.
    progress : bool, optional
        Show a progress bar (default: when standard error is a terminal).
    log : callable, optional
        Called with a line per failure (default: written above the progress bar).

    Returns
    -------
    Summary

    Examples
    --------
    >>> import tempfile
    >>> out = tempfile.mkdtemp()
    >>> s = run_dataset(["cube", "l-prism"], out, Job(contact="soft", mu=0.5, top=1), workers=1,
    ...                 progress=False)
    >>> s.done, s.computed
    (2, 2)
    >>> run_dataset(["cube", "l-prism"], out, Job(contact="soft", mu=0.5, top=1), workers=1,
    ...             progress=False).skipped
    2
    """
    from tqdm import tqdm

    paths = expand_inputs(inputs)
    if job.mode == "synthesize":  # a hand no object can serve: refuse before any work
        from .objects import POLYGONS
        from .synthesis.best import check_hand

        for dim in sorted({2 if p.suffix.lower() in POLYGON_SUFFIXES or str(p) in POLYGONS
                           else 3 for p in paths}):
            check_hand(dim, job.fingers, job.contact, job.mu, top=job.top,
                       construction=job.construction, method=job.method)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: is a file, not a folder")
    folder = out / "objects"
    folder.mkdir(parents=True, exist_ok=True)
    _check_job(out, job)
    held = _read_records(folder)
    names = {record_name(p): p for p in paths}
    keep = {"done"} if retry_failed else set(STATUSES)
    run = _Run({n: p for n, p in names.items()
                if n not in held or held[n].get("status") not in keep})
    skipped = len(names) - len(run.todo)
    records = {n: held[n] for n in names if n in held}
    workers = workers or os.cpu_count() or 1
    start = time.perf_counter()
    computed, interrupted = 0, False
    bar = tqdm(total=len(run.todo), unit="obj", desc="objects", file=sys.stderr,
               disable=not progress if progress is not None else None, dynamic_ncols=True)
    say = log or (lambda line: bar.write(line, file=sys.stderr))

    def finish(name: str, record: dict[str, Any]) -> None:
        nonlocal computed
        _write_atomically(folder / name, json.dumps(record) + "\n")
        records[name] = record
        run.todo.pop(name, None)
        computed += 1
        bar.update(1)
        if record["status"] != "done":
            say(f"forceclosure: {record['status']}: {record['error']}")

    try:
        if executor is None and workers == 1:
            for name, path in list(run.todo.items()):
                finish(name, process_object(path, job))
        elif executor is None:
            _local_pool(workers, run, job, finish)
        else:
            _drain(executor, run, job, finish, width=0)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        bar.close()
        write_table(out, records.values())
    statuses = [r.get("status") for r in records.values()]
    return Summary(objects=len(names), done=statuses.count("done"),
                   failed=statuses.count("failed"), timeout=statuses.count("timeout"),
                   computed=computed, skipped=skipped,
                   seconds=time.perf_counter() - start, workers=workers, out=out,
                   interrupted=interrupted)


def _failed(path: Path, error: str) -> dict[str, Any]:
    return {"path": _key(path), "name": path.stem, "status": "failed", "error": error,
            "seconds": None}


def _drain(executor: Executor, run: _Run, job: Job,
           finish: Callable[[str, dict[str, Any]], None], width: int) -> list[str]:
    """Submit every pending object and finish each as its result arrives.

    Returns the objects a broken local pool (a worker killed) may have been
    running: the first ``width`` still pending, as the pool hands them out in
    order; everything else pending is simply submitted again. On
    other executors an object whose future fails (Dask's KilledWorker, after
    the scheduler's own retries) is recorded as failed.
    """
    order = list(run.todo)
    futures: dict[Future, str] = {executor.submit(process_object, run.todo[n], job): n
                                  for n in order}
    broken = False
    for future in as_completed(futures):
        name = futures[future]
        try:
            record = future.result()
        except BrokenProcessPool:
            broken = True
            continue
        except Exception as e:  # the executor lost the object (e.g. KilledWorker)
            why = str(e).splitlines()[0] if str(e) else ""
            finish(name, _failed(run.todo[name], f"{run.todo[name].name}: its worker died "
                                                 f"({type(e).__name__}: {why})"))
            continue
        finish(name, record)
    return [n for n in order if n in run.todo][:width] if broken else []


def _context() -> multiprocessing.context.BaseContext:
    """Workers forked from a clean server process: forking this one is unsafe once its
    compiled kernels have started OpenMP threads."""
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["forceclosure.dataset", "forceclosure.synthesis"])
    return context


def _one_thread_each() -> None:
    """The pool already uses every core: each worker's kernels run on one thread."""
    import numba

    numba.set_num_threads(1)


def _local_pool(workers: int, run: _Run, job: Job,
                finish: Callable[[str, dict[str, Any]], None]) -> None:
    """Everything on a local process pool, surviving killed workers.

    After a worker dies, the objects it may have been running are run one at
    a time on fresh pools, so a second death names its object exactly; an
    object that kills its worker :data:`MAX_CRASHES` times is recorded as
    failed. Then the rest goes on in parallel.
    """
    suspects: list[str] = []
    while run.todo:
        with ProcessPoolExecutor(workers, mp_context=_context(),
                                 initializer=_one_thread_each) as pool:
            if not suspects:
                suspects = _drain(pool, run, job, finish, width=workers + 1)
                continue
            name = suspects[0]
            try:
                record = pool.submit(process_object, run.todo[name], job).result()
            except BrokenProcessPool:
                run.crashes[name] = run.crashes.get(name, 0) + 1
                if run.crashes[name] < MAX_CRASHES:
                    continue
                path = run.todo[name]
                record = _failed(path, f"{path.name}: its worker process died "
                                       f"{MAX_CRASHES} times on it (out of memory?)")
            suspects.pop(0)
            finish(name, record)
