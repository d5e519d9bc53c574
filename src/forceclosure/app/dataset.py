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
  atomically (a temporary file in the same folder, synced, then renamed)
  by the driver as soon as the object finishes, whatever worker computed
  it. Each record carries the job's identity (the options that change
  results) and its input's fingerprint (a SHA-256 of the object file, of
  the meshes a URDF names and, in analysis, of the grasp file). Objects
  with a record are skipped on a re-run (failed ones too, unless
  ``retry_failed``); a record that is damaged (not JSON, not a record,
  fields missing or of the wrong type), foreign (copied from another
  object's) or stale (another job's, or its input changed since) is
  computed again, with a warning;
* ``.lock``: held (``flock``) by the run writing to ``DIR``; a second run
  on the same ``DIR`` is refused in one line while the first is alive (the
  kernel drops the lock when its holder dies, however it dies);
* ``results.parquet``: one row per object (status, timings, best grasps
  and region sizes), rebuilt from the records at the end of every run,
  also an interrupted one.

A bad or unreadable object is recorded as ``failed`` with its one-line
error; an object over the time limit as ``timeout``. On the local pool
(pebble's ``ProcessPool``) each object runs in a worker process that can
be killed, so the time limit holds inside compiled code too: the worker is
asked to stop at the limit (``SIGALRM``, between bytecodes) and killed
:data:`HARD_GRACE` seconds later if it has not. A worker that dies
(killed, out of memory) costs only the object it was running, which is run
again on a fresh worker; an object that kills workers :data:`MAX_CRASHES`
times is recorded as ``failed``. A watchdog kills a worker stopped
(``SIGSTOP``) for :data:`STALL_SECONDS`, and its object is run again.
Workers die with the run (Linux: ``PR_SET_PDEATHSIG``), so a killed run
leaves no computation behind. ``workers=1`` without a time limit runs in
this process. On Dask the scheduler retries objects whose worker died,
and the time limit is raised between bytecodes only (a Dask worker's
thread cannot be killed).

A full disk (any error writing to ``DIR``) stops the run with one line:
the records written so far are kept, the temporary files removed, and the
same command resumes once there is room.
"""

from __future__ import annotations

import ctypes
import glob
import hashlib
import json
import math
import multiprocessing
import os
import queue
import re
import signal
import socket
import string
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import Executor, Future, as_completed
from concurrent.futures import TimeoutError as FutureTimeout
from contextlib import contextmanager, suppress
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any, Literal, Protocol

import numpy as np

from ..errors import InputError, printable
from ..extras import require
from ..files.outdir import atomic_file, locked, remove_temporaries, write_atomically
from ..objects.io import MESH_SUFFIXES, POLYGON_SUFFIXES, ROBOT_SUFFIXES
from ..objects.urdf import mesh_files
from ..verdicts import Verdict, VerdictCode
from .interrupt import holding
from .progress import ProgressLines, bar_size, every_from_environment
from .workers import Relay, Watchdog, die_with_run, number_worker, tell_compiling, tell_dask_run

__all__ = [
    "COLUMNS",
    "GRASP_SUFFIXES",
    "HARD_GRACE",
    "MAX_CRASHES",
    "OBJECT_SUFFIXES",
    "STALL_SECONDS",
    "Job",
    "LabelJob",
    "ObjectTimeout",
    "Summary",
    "deadline",
    "expand_inputs",
    "fingerprint",
    "grasp_file_of",
    "printable",
    "process_object",
    "record_name",
    "row_of",
    "run_dataset",
    "surface_distance",
    "write_table",
]

#: Files a folder contributes: polygons, meshes, robot descriptions.
OBJECT_SUFFIXES = POLYGON_SUFFIXES + MESH_SUFFIXES + ROBOT_SUFFIXES
#: Grasp files given per object (analysis mode), not objects themselves.
GRASP_SUFFIXES = (".grasps.json", ".grasps.npz")
#: A worker may die this many times on one object before it is recorded as failed.
MAX_CRASHES = 3
#: Contacts farther than this (relative to the object's size) are off its surface.
SURFACE_RTOL = 1e-3
STATUSES = ("done", "failed", "timeout")
#: Seconds past the time limit after which a worker that has not stopped is killed.
HARD_GRACE = 2.0
#: Seconds a worker may stay stopped (SIGSTOP) before the watchdog kills it.
STALL_SECONDS = 30.0
#: The placeholders a ``--grasps`` pattern may use, as plain names.
PLACEHOLDERS = ("dir", "stem", "name")
#: Damaged, foreign or stale records warned about one by one; the rest are counted.
_WARNED = 20


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
        Seconds one object may take; None (or ``inf``) for no limit.
    allow_open : bool
        Accept open and non-manifold meshes (``load_object(..., allow_open=True)``);
        part of the job's identity, since it changes which objects load and how.
    allow_outside_meshes : bool
        Let a URDF name meshes outside its folder (or its package's); refused
        by default (:func:`forceclosure.objects.urdf.check_mesh_inside`).
    """

    mode: Literal["synthesize", "analyze"] = "synthesize"
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
    allow_outside_meshes: bool = False

    def __post_init__(self) -> None:
        if self.mode not in ("synthesize", "analyze"):
            raise InputError(f"mode must be synthesize or analyze, got {self.mode!r}")
        if self.timeout is not None and not self.timeout > 0:
            raise InputError(f"--timeout must be a positive number of seconds, got "
                             f"{self.timeout:g}")
        if self.timeout is not None and math.isinf(self.timeout):
            object.__setattr__(self, "timeout", None)  # inf: no limit
        if self.samples < 1:
            raise InputError(f"--samples must be at least 1, got {self.samples}")
        if self.fingers is not None and self.fingers < 1:
            raise InputError(f"--fingers must be at least 1, got {self.fingers}")
        _check_pattern(self.grasps)

    def identity(self) -> dict[str, Any]:
        """The options that decide the results (the time limit does not)."""
        if self.mode == "analyze":
            return {"mode": "analyze", "grasps": self.grasps, "allow_open": self.allow_open,
                    "allow_outside_meshes": self.allow_outside_meshes}
        record = asdict(self)
        record.pop("timeout")
        return record


class LabelJob(Protocol):
    """A job that labels each object itself, as
    :class:`forceclosure.app.dataset_gripper.GripperJob` does: what :func:`run_dataset`
    asks of a job other than a :class:`Job` (its optional ``store``, ``write_tables``,
    ``check`` and ``output_folders`` are looked up when there)."""

    @property
    def mode(self) -> Literal["gripper"]:
        """The dispatch key of :func:`process_object`."""
        ...

    @property
    def timeout(self) -> float | None:
        """Seconds one object may take; None for no limit."""
        ...

    @property
    def allow_open(self) -> bool:
        """Accept open and non-manifold meshes (as :class:`Job`'s)."""
        ...

    @property
    def allow_outside_meshes(self) -> bool:
        """Let a URDF name meshes outside its folder (as :class:`Job`'s)."""
        ...

    def identity(self) -> dict[str, Any]:
        """The options that decide the results (``job.json``'s content)."""
        ...

    def label(self, obj: Any, path: Path) -> dict[str, Any]:
        """The record's fields for one loaded object."""
        ...

    def warm_up(self) -> None:
        """Run its compiled kernels once (a pool worker, before its first object)."""
        ...


def _check_pattern(pattern: str) -> None:
    """A ``--grasps`` pattern may use :data:`PLACEHOLDERS`, as plain names: no attribute or
    index (``{dir.__class__}``), no nested field, since ``str.format`` would evaluate them."""
    def refuse(why: str) -> InputError:
        return InputError(f"--grasps {pattern[:200]!r}: {why}; {{dir}}, {{stem}} and {{name}} "
                          "are the placeholders it may use, as plain names")

    try:
        parsed = list(string.Formatter().parse(pattern))
    except ValueError as e:
        raise refuse(str(e)) from None
    for _, field_name, spec, _ in parsed:
        if field_name is None:
            continue
        if field_name not in PLACEHOLDERS:
            raise refuse(f"{{{field_name[:60]}}} is not one")
        if spec and ("{" in spec or "}" in spec):
            raise refuse(f"{{{field_name}:{spec[:60]}}} nests a field")
    try:
        pattern.format(dir="", stem="", name="")
    except (KeyError, IndexError, ValueError) as e:
        raise refuse(f"{type(e).__name__}: {e}") from None


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
    interrupted : bool
    incomplete : int
        Synthesis: objects done whose search left sites undecided (``undecided`` above 0
        in their records, ``complete`` false): grasps may be missing there.
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
    incomplete: int = 0

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
        if self.incomplete:
            lines.append(f"not complete: {self.incomplete} object"
                         f"{'s' if self.incomplete != 1 else ''} with sites undecided (grasps "
                         "may be missing there; the table's complete and undecided columns)")
        lines.append(f"results: {self.out / 'results.parquet'} (one row per object), "
                     f"{self.out / 'objects'} (full records)")
        if self.interrupted:
            lines.append("interrupted: run the same command again to resume")
        return "\n".join(lines)


# -- the input set --------------------------------------------------------------------------

def expand_inputs(inputs: Iterable[str | Path], exclude: str | Path | None = None,
                  folders: Iterable[str | Path] = ()) -> list[Path]:
    """Object files from files, folders (searched recursively) and glob patterns.

    A folder contributes its polygon, mesh and URDF files, but not the mesh
    files its URDFs name (the URDF stands for them, with its scale) nor
    grasp files (``*.grasps.json``). A file named directly is always taken.
    The own files of the dataset whose results folder is ``exclude`` (its
    ``job.json``, ``exports.json``, ``*.parquet`` and the records folder
    ``objects/``: JSON too) and files inside ``folders`` (the job's pictures
    and exports) are left out of folders and glob patterns; the rest of
    ``exclude`` (an input folder inside it, say) is searched as any folder.

    Examples
    --------
    >>> import pybullet_data, os
    >>> urdfs = os.path.join(pybullet_data.getDataPath(), "random_urdfs")
    >>> found = expand_inputs([urdfs])
    >>> len(found), found[0].name
    (1000, '000.urdf')
    """
    from ..objects import POLYGONS, POLYHEDRA

    named: list[Path] = []
    walked: list[Path] = []
    skip = _own_output(exclude, folders)
    for item in inputs:
        path = Path(item)
        if path.is_file() or (not path.exists() and str(item) in {*POLYGONS, *POLYHEDRA}):
            named.append(path)  # a file, or a bundled object's name
        elif path.is_dir():
            walked += [p for p in sorted(path.rglob("*"))
                       if p.is_file() and p.suffix.lower() in OBJECT_SUFFIXES
                       and not p.name.lower().endswith(GRASP_SUFFIXES) and not skip(p)]
        else:
            matches = sorted(Path(m) for m in glob.glob(str(item), recursive=True))
            matches = [m for m in matches if m.is_file()]
            if not matches:
                raise InputError(f"{item}: no such file or folder, and no files match it")
            matches = [m for m in matches if not skip(m)]
            named += matches
    meshes_of_urdfs = set()
    for p in walked:
        if p.suffix.lower() in ROBOT_SUFFIXES:
            # a bad URDF (or one naming a symbolic link loop) is recorded as failed in its turn
            with suppress(InputError, OSError, RuntimeError):
                for m in mesh_files(p):
                    with suppress(OSError, RuntimeError):
                        meshes_of_urdfs.add(str(m.resolve()))
    walked = [p for p in walked if _key(p) not in meshes_of_urdfs]
    unique: dict[str, Path] = {}
    for p in named + walked:
        unique.setdefault(_key(p), p)
    return sorted(unique.values(), key=lambda p: str(p))


def _own_output(out: str | Path | None, folders: Iterable[str | Path] = ()
                ) -> Callable[[Path], bool]:
    """Whether a path is one of the files a dataset writes (symbolic links followed): in its
    results folder ``out`` (None: none), ``job.json``, ``exports.json``, ``*.parquet`` and
    the records folder ``objects/``; anything inside ``folders``."""
    from .dataset_options import EXPORTS_FILE

    tops: list[Path] = []
    files: set[Path] = set()
    top: Path | None = None
    try:
        if out is not None:
            top = Path(out).resolve()
            files = {top / "job.json", top / EXPORTS_FILE}
            tops.append(top / "objects")
        tops += [Path(f).resolve() for f in folders]
    except (OSError, RuntimeError):
        pass

    def own(path: Path) -> bool:
        try:
            where = path.resolve()
        except (OSError, RuntimeError):
            return False
        return (where in files or (where.parent == top and where.suffix.lower() == ".parquet")
                or any(where.is_relative_to(t) for t in tops))
    return own


def _key(path: Path) -> str:
    """What identifies an object: its absolute path (a bundled object: its name)."""
    try:
        return str(path.resolve()) if path.exists() else str(path)
    except (OSError, RuntimeError):  # a symbolic link loop: its path as given, made absolute
        return str(path.absolute())


def record_name(path: Path) -> str:
    """The file name of an object's record: readable, and unique per object."""
    key = _key(path)
    stem = re.sub(r"[^A-Za-z0-9._-]+", "_", path.name)[:60]
    return f"{stem}-{hashlib.sha1(key.encode()).hexdigest()[:12]}.json"


# -- one object (runs on a worker) ----------------------------------------------------------

class ObjectTimeout(BaseException):
    """An object ran over its time limit. A ``BaseException``, like ``KeyboardInterrupt``,
    so that no ``except Exception`` on the way (in a file reader, say) swallows it."""


#: Seconds between repeats of :class:`ObjectTimeout` once the time limit has passed: code
#: that catches every exception (trimesh's optional imports catch ``BaseException``) may
#: swallow one, never the next.
REPEAT = 0.1


@contextmanager
def deadline(seconds: float | None) -> Iterator[None]:
    """Raise :class:`ObjectTimeout` in this thread after ``seconds``, and again every
    :data:`REPEAT` seconds until it leaves the block.

    The main thread (a process-pool worker) uses ``SIGALRM``; another thread
    (a Dask worker's) gets the exception raised in it asynchronously. Either
    way it arrives between Python bytecodes, so one long call into compiled
    code (a hull of a huge mesh) finishes first.
    """
    if seconds is None:
        yield
        return
    if threading.current_thread() is threading.main_thread():
        armed = [True]

        def alarm(signum, frame):
            if armed[0]:  # a repeat landing while the block is left raises nothing
                raise ObjectTimeout

        previous = signal.signal(signal.SIGALRM, alarm)
        outer, _ = signal.setitimer(signal.ITIMER_REAL, seconds, REPEAT)
        start = time.monotonic()
        try:
            yield
        finally:
            armed[0] = False
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
            if outer > 0:  # an alarm set around ours (a test runner's time limit) goes on
                signal.setitimer(signal.ITIMER_REAL,
                                 max(outer - (time.monotonic() - start), 1e-3))
        return
    ident, lock, done = threading.get_ident(), threading.Lock(), threading.Event()

    def fire() -> None:
        wait = seconds
        while not done.wait(wait):
            with lock:
                if done.is_set():
                    return
                ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(ident),
                                                           ctypes.py_object(ObjectTimeout))
            wait = REPEAT

    timer = threading.Thread(target=fire, daemon=True)
    timer.start()
    try:
        yield
    finally:
        with lock:
            done.set()
        # an exception set but not yet raised must not escape the block
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(ident), None)


def _timed_out(error: BaseException) -> bool:
    """Whether ``error`` is the time limit, or carries it: a limit landing inside a call
    into compiled code (a numba kernel's dispatcher) comes out of it as ``SystemError: ...
    returned a result with an exception set``, the :class:`ObjectTimeout` its cause."""
    seen: set[int] = set()
    link: BaseException | None = error  # then its cause or context, to the chain's end
    while link is not None and id(link) not in seen:
        if isinstance(link, ObjectTimeout):
            return True
        seen.add(id(link))
        link = link.__cause__ or link.__context__
    return False


def _describe(obj) -> dict[str, Any]:
    # units: the file's own (an SVG's mm, a GeoJSON's "units"), None where it states none
    # (every mesh): the lengths and areas of the record are in them
    if obj.dim == 2:
        return {"kind": "polygon", "size": obj.size, "edges": len(obj.edges),
                "triangles": 0, "units": obj.units}
    return {"kind": "polyhedron", "size": obj.size, "faces": len(obj.faces),
            "triangles": len(obj.triangles), "units": getattr(obj, "units", None)}


def _synthesize(obj, job: Job) -> dict[str, Any]:
    from ..synthesis.best import synthesize

    result = synthesize(obj, job.fingers, job.contact, job.mu, top=job.top, margin=job.margin,
                        construction=job.construction, method=job.method,
                        samples=job.samples, seed=job.seed)
    grasps = [r.to_dict() for r in result.found]
    # complete: nothing the hand can do is missing; undecided: sites whose regions could
    # not be proved (grasps may be missing there), as synthesize --json says
    return {"fingers": result.fingers, "contact": result.contact, "mu": result.mu,
            "method": result.method, "grasps": grasps, "complete": result.complete,
            "undecided": result.undecided}


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


def fingerprint(path: str | Path, job: Job | LabelJob) -> str:
    """The SHA-256 of everything an object's result is computed from: the object file, the
    mesh files a URDF names, and in analysis the grasp file (or that it is missing).

    A record whose input's fingerprint differs is stale, and computed again.
    Files that are not regular files (devices, FIFOs, symbolic link loops)
    are not read: their kind stands for them.

    Examples
    --------
    >>> len(fingerprint("cube", Job())), fingerprint("cube", Job()) == fingerprint("hexagon", Job())
    (64, False)
    """
    from .. import __version__

    path = Path(path)
    digest = hashlib.sha256()

    def add(label: str, file: Path) -> None:
        digest.update(label.encode("utf-8", "surrogateescape") + b"\0")
        try:
            if not file.is_file():
                digest.update(b"missing or not a regular file")
                return
            with open(file, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    digest.update(block)
        except (OSError, RuntimeError) as e:
            digest.update(f"unreadable: {type(e).__name__}".encode())
        digest.update(b"\0")

    if not path.exists() and not path.is_symlink():  # a bundled object
        digest.update(f"bundled {path} {__version__}".encode("utf-8", "surrogateescape"))
    else:
        add("object", path)
    if path.suffix.lower() in ROBOT_SUFFIXES:
        with suppress(InputError, OSError, RuntimeError, ValueError):
            for mesh in mesh_files(path):
                add(f"mesh {mesh}", mesh)
    if job.mode == "analyze":
        try:
            add("grasps", grasp_file_of(path, job.grasps))
        except (InputError, OSError, RuntimeError):
            digest.update(b"no grasp file")
    return digest.hexdigest()


def surface_distance(obj, points: np.ndarray) -> np.ndarray:
    """Distance of each point to the object's boundary."""
    if obj.dim == 2:
        import shapely

        return shapely.distance(obj.to_shapely().boundary, shapely.points(points))
    return np.array([obj.locate(p)[2] for p in points])


def _analyze(obj, path: Path, job: Job) -> dict[str, Any]:
    from ..io.grasp_arrays import analyze_npz, iter_chunks, open_npz
    from ..io.grasp_file import parse_grasp_file, result_record

    source = grasp_file_of(path, job.grasps)
    if not source.is_file():
        raise InputError(f"{path.name}: no grasp file {source}")
    if source.suffix.lower() == ".npz":
        info = open_npz(str(source))
        if info.dim != obj.dim:
            raise InputError(f"{source.name}: {info.dim}-D grasps for a {obj.dim}-D object")
        results = analyze_npz(str(source), epsilon=True)
        assert results.epsilon is not None  # asked for (epsilon=True): an array, NaN where none
        # the contacts of the grasps analysed: a truncated member keeps the chunks before it,
        # as analyze_npz (and 'forceclosure analyze') do
        parts = []
        with suppress(InputError):
            for c in iter_chunks(info):
                parts.append(c["points"].reshape(-1, obj.dim))
        points = np.concatenate(parts) if parts else np.empty((0, obj.dim))
        counts = results.counts()
        closed = results.epsilon[results.code == VerdictCode.CLOSURE]
        verdicts = results.code.tolist()
        errors = results.errors
        eps_median = float(np.median(closed)) if len(closed) else None
        per_grasp: list[Any] = []
    else:
        grasp_file = parse_grasp_file(source.read_text(encoding="utf-8"), source.name)
        per_grasp = [result_record(entry, grasp_file.cone)[0] for entry in grasp_file.grasps]
        names = {v.value: int(v.code) for v in Verdict}
        verdicts = [names.get(r.get("verdict"), -1) for r in per_grasp]
        counts = {k: verdicts.count(c) for k, c in (*names.items(), ("errors", -1))}
        errors = [r["error"] for r in per_grasp if "error" in r]
        eps = [r["epsilon"] for r in per_grasp if r.get("verdict") == "closure"
               and r.get("epsilon") is not None]
        eps_median = float(np.median(eps)) if eps else None
        # an entry has its contacts exactly when it has no error (parse_grasp_file)
        good = [(e.label, e.contacts) for e in grasp_file.grasps
                if e.error is None and e.contacts is not None]
        for label, contacts in good:
            if any(len(c.point) != obj.dim for c in contacts):
                raise InputError(f"{source.name}: {label}: "
                                 f"{len(contacts[0].point)}-D contacts for a {obj.dim}-D "
                                 "object")
        points = np.array([c.point for _, contacts in good for c in contacts]).reshape(
            -1, obj.dim)
    finite = points[np.all(np.isfinite(points), axis=1)]
    off = int(np.sum(surface_distance(obj, finite) > SURFACE_RTOL * obj.size)) if len(
        finite) else 0
    return {"grasp_file": str(source), "grasps": len(verdicts), **counts,
            "epsilon_median": eps_median, "off_surface": off, "verdicts": verdicts,
            "grasp_errors": errors, "results": per_grasp}


def process_object(path: str | Path, job: Job | LabelJob) -> dict[str, Any]:
    """Run the job on one object and return its record; never raises for a bad object.

    Examples
    --------
    >>> record = process_object("cube", Job(contact="soft", mu=0.5, top=1))
    >>> record["status"], len(record["grasps"])
    ('done', 1)
    >>> process_object("nowhere.stl", Job())["error"]
    "nowhere.stl: no such file, and no bundled object of that name (see 'forceclosure objects')"
    """
    from ..objects.io import load_object

    path = Path(path)
    record: dict[str, Any] = {"path": _key(path), "name": path.stem, "status": "done",
                              "error": None, "worker": f"{socket.gethostname()}:{os.getpid()}"}
    if job.timeout is not None:
        # trimesh's own import catches BaseException around its optional imports: a time
        # limit firing there would be swallowed and leave trimesh broken in this process
        import trimesh  # noqa: F401
    start = time.perf_counter()
    try:
        with deadline(job.timeout):
            obj = load_object(path, allow_open=job.allow_open,
                              allow_outside_meshes=job.allow_outside_meshes)
            record.update(_describe(obj))
            record["load_seconds"] = time.perf_counter() - start
            if job.mode == "gripper":  # forceclosure.app.dataset_gripper.GripperJob
                record.update(job.label(obj, path))
            else:
                record.update(_synthesize(obj, job) if job.mode == "synthesize"
                              else _analyze(obj, path, job))
    except InputError as e:
        record.update(status="failed", error=str(e))
    except MemoryError:
        record.update(status="failed", error=f"{path.name}: out of memory")
    except (ObjectTimeout, Exception) as e:
        if _timed_out(e):
            record.update(status="timeout", error=f"{path.name}: over the time limit of "
                                                  f"{job.timeout:g} s")
        else:  # an internal error: one line, and the run goes on
            first = str(e).splitlines()[0] if str(e) else ""
            record.update(status="failed", error=f"{path.name}: internal error: "
                                                 f"{type(e).__name__}: {first}")
    record["seconds"] = time.perf_counter() - start
    return record


# -- the results folder ------------------------------------------------------------------

def _jobs_of_records(folder: Path, job: Any = None) -> list[dict[str, Any]]:
    """The distinct jobs (as :func:`_comparable` to ``job``) the readable records in
    ``folder`` say they belong to."""
    jobs: dict[str, dict[str, Any]] = {}
    for file in sorted(folder.glob("*.json")) if folder.is_dir() else []:
        try:
            record = json.loads(file.read_text(encoding="utf-8"))
        except (OSError, ValueError, UnicodeDecodeError, RecursionError):
            continue
        if isinstance(record, dict) and isinstance(record.get("job"), dict):
            jobs.setdefault(json.dumps(_comparable(record["job"], job), sort_keys=True),
                            record["job"])
    return list(jobs.values())


def _repaired_job(out: Path, path: Path, wanted: dict[str, Any],
                  warn: Callable[[str], object], job: Any = None) -> dict[str, Any]:
    """A damaged ``job.json`` (truncated, not JSON, not an object) rebuilt from the records'
    own copies of their job, or refused in one line saying the way out."""
    jobs = _jobs_of_records(out / "objects", job)
    if len(jobs) > 1:
        raise InputError(f"{path}: damaged, and the records in {out / 'objects'} belong to "
                         f"{len(jobs)} jobs; remove {path.name} to keep those of this job (the "
                         "others are computed again), or use another --out")
    held = jobs[0] if jobs else wanted
    write_atomically(path, json.dumps(held, indent=2) + "\n")
    warn(f"forceclosure: warning: {path}: damaged; rebuilt from "
         + (f"the job its {out / 'objects'} records name" if jobs else
            "this run's options (no record names a job)"))
    return held


def _with_defaults(stored: dict[str, Any], job: Any) -> dict[str, Any]:
    """A job as ``job.json`` or a record's ``"job"`` holds it, with the options added since it
    was written filled in with what their absence means (their defaults then, and now).

    Parameters
    ----------
    stored : dict
        The job read from ``job.json`` or from a record's ``"job"``.
    job : Job or forceclosure.app.dataset_gripper.GripperJob
        This run's job: its class's ``IDENTITY_DEFAULTS`` (if any) say which options were
        added, and their defaults.

    Returns
    -------
    dict
        A new dict, ready to compare with ``job.identity()``.

    Examples
    --------
    >>> _with_defaults({"mode": "analyze", "grasps": None}, Job(mode="analyze"))
    {'mode': 'analyze', 'grasps': None, 'allow_open': False, 'allow_outside_meshes': False}
    """
    filled = dict(stored)
    filled.setdefault("allow_open", False)  # written before the option existed
    filled.setdefault("allow_outside_meshes", False)
    for key, value in getattr(job, "IDENTITY_DEFAULTS", {}).items():
        filled.setdefault(key, value)  # options added since the file was written
    return filled


def _comparable(stored: dict[str, Any], job: Any) -> dict[str, Any]:
    """A stored job as compared with this run's: :func:`_with_defaults`, without the options
    that only choose the outputs redrawn each run (the job class's ``OUTPUT_OPTIONS``:
    pictures, exports)."""
    if not isinstance(stored, dict):
        return stored
    filled = _with_defaults(stored, job)
    for key in getattr(job, "OUTPUT_OPTIONS", ()):
        filled.pop(key, None)
    return filled


def _differences(held: dict[str, Any], wanted: dict[str, Any], within: str = "") -> list[str]:
    """Where two jobs differ, one phrase a key (``"mu 0.5 there, 0.7 here"``; in a dict
    both hold, such as the hand's sizes, a phrase per differing size: only when no other key
    differs, since those sizes may follow from the others, as the generic hand's width)."""
    phrases, nested = [], []
    for key in sorted(set(held) | set(wanted)):
        there, here = held.get(key), wanted.get(key)
        if there == here:
            continue
        if isinstance(there, dict) and isinstance(here, dict):
            nested += _differences(there, here, f"{within}{key} ")
        elif key not in held and isinstance(here, dict):  # a job file older than the key
            phrases.append(f"{within}{key} not recorded there (an older forceclosure), "
                           "recorded here")
        else:
            phrases.append(f"{within}{key} {there!r} there, {here!r} here")
    return phrases or nested


def _check_job(out: Path, job: Job | LabelJob, warn: Callable[[str], object] | None = None) -> None:
    path = out / "job.json"
    wanted = job.identity()
    warn = warn or (lambda line: print(printable(line), file=sys.stderr))
    if path.exists():
        try:
            held = json.loads(path.read_text(encoding="utf-8"))
        except (ValueError, UnicodeDecodeError, RecursionError):
            held = None
        if not isinstance(held, dict):
            held = _repaired_job(out, path, wanted, warn, job)
        same = _comparable(wanted, job)
        if isinstance(held, dict):
            held = _comparable(held, job)
        if held != same:
            what = (", ".join(_differences(held, same)[:3]) if isinstance(held, dict)
                    else "the whole file")
            raise InputError(f"{out} holds results of another job ({what}); use another "
                             "--out, or the same options to resume")
        if json.loads(path.read_text(encoding="utf-8")) != wanted:  # this run's outputs
            write_atomically(path, json.dumps(wanted, indent=2) + "\n")
    else:
        write_atomically(path, json.dumps(wanted, indent=2) + "\n")


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
           ("errors", "int64"), ("epsilon_median", "float64"), ("off_surface", "int64"),
           # gripper (forceclosure.app.dataset_gripper; also grasps, contact, mu, closure, marginal,
           # none and epsilon_median above)
           ("width", "float64"), ("pad_radius", "float64"), ("seed", "int64"),
           ("least_friction_median", "float64"), ("collides", "int64"),
           ("closure_clear", "int64"), ("attempts", "int64"), ("rejected", "int64"),
           ("labels_file", "string"),
           # synthesis, added later (appended, so that every column keeps its place): whether
           # the search is complete, and how many sites it left undecided (null in records
           # written before)
           ("complete", "bool"), ("undecided", "int64"),
           # the object's units (an SVG's "mm", a GeoJSON's own), null where the file states
           # none (meshes) and in records written before this column
           ("units", "string"))


def row_of(record: dict[str, Any]) -> dict[str, Any]:
    """The results.parquet row of an object's record: scalars, and the best grasp's sizes
    (areas on polyhedra, lengths on polygons)."""
    row = {name: record.get(name) for name, _ in COLUMNS}
    grasps = record.get("grasps")
    if isinstance(grasps, list):  # synthesis
        row["grasps"] = len(grasps)
        if grasps:
            best = grasps[0]  # a region set's record (RegionSet.to_dict)
            if "min_size" not in best:  # kept from a run before records had these keys
                kind = "area" if "min_area" in best else "length"
                best = {**best, "min_size": best[f"min_{kind}"], "sizes": best[f"{kind}s"],
                        "relative_min_size": best[f"relative_min_{kind}"]}
            row["best_min_region"] = best["min_size"]
            row["best_relative_min_region"] = best["relative_min_size"]
            row["best_region_sizes"] = best["sizes"]
            where = best.get("faces", best.get("edges"))
            if where is None:  # a soft finger on a vertex (construction "vertices")
                where = {k: best[k] for k in ("vertex", "edge", "other_vertex") if k in best}
            row["best_faces"] = json.dumps(where)
        row["all_certified"] = all(g["certificate"]["holds"] for g in grasps)
    return row


def _table(records: Iterable[dict[str, Any]]) -> Any:
    pa = require("pyarrow", "the dataset's table", "table")

    types = {"string": pa.string(), "float64": pa.float64(), "int64": pa.int64(),
             "bool": pa.bool_(), "list<float64>": pa.list_(pa.float64())}
    schema = pa.schema([(name, types[t]) for name, t in COLUMNS])
    rows = sorted((row_of(r) for r in records), key=lambda r: (r["path"] or ""))
    return pa.Table.from_pylist(rows, schema=schema)


def write_table(out: Path, records: Iterable[dict[str, Any]]) -> Path:
    """Write ``out/results.parquet`` (atomically) from object records."""
    pq = require("pyarrow.parquet", "the dataset's table", "table")
    table = _table(records)
    path = out / "results.parquet"
    with atomic_file(path) as f:
        pq.write_table(table, f)
    return path


def _damage(record: Any, path: Path, identity: dict[str, Any], stamp: str,
            job: Any = None) -> str | None:
    """Why a record held in ``DIR`` cannot stand for the object at ``path`` in this job, or
    None when it can (its job compared as ``job.json``'s: :func:`_comparable`)."""
    if not isinstance(record, dict):
        return f"not a record (a JSON {type(record).__name__})"
    missing = [k for k in ("path", "name", "status", "error", "job", "input")
               if k not in record]
    if missing:
        if missing == ["job", "input"]:
            return "written by an older forceclosure (no job and input stamps)"
        return f"fields missing ({', '.join(missing)})"
    if record["path"] != _key(path):
        return f"the record of another object ({str(record['path'])[:200]!r})"
    if record["status"] not in STATUSES:
        return f"unknown status {str(record['status'])[:40]!r}"
    if _comparable(record["job"], job) != _comparable(identity, job):
        return "made by another job (other options)"
    if record["input"] != stamp:
        return "its input changed since (object, meshes or grasp file)"
    try:
        _table([record])
    except Exception as e:  # a field of the wrong type: the Parquet build would fail
        return f"a field of the wrong type ({type(e).__name__})"
    return None


def _held(folder: Path, names: dict[str, Path], identity: dict[str, Any],
          stamps: dict[str, str], say: Callable[[str], object],
          check: Callable[[Path, dict[str, Any]], str | None] | None = None,
          job: Any = None) -> dict[str, dict[str, Any]]:
    """The records in ``folder`` that stand for their objects; the others are warned about
    (the first :data:`_WARNED` one by one, then counted) and will be computed again."""
    held, bad = {}, 0
    for name, path in names.items():
        file = folder / name
        if not file.exists():
            continue
        try:
            record = json.loads(file.read_text(encoding="utf-8"))
            why = _damage(record, path, identity, stamps[name], job)
            if why is None and check is not None:  # the job's own files (gripper: labels)
                why = check(folder, record)
        except (OSError, ValueError, UnicodeDecodeError, RecursionError) as e:
            why = f"not readable JSON ({type(e).__name__})"
        if why is None:
            held[name] = record
            continue
        bad += 1
        if bad <= _WARNED:
            say(f"forceclosure: warning: {file}: {why}; computing it again")
    if bad > _WARNED:
        say(f"forceclosure: warning: {bad - _WARNED} more records damaged, foreign or stale; "
            "computing them again")
    return held


class _OutputFailed(Exception):
    """Writing to ``DIR`` failed (a full disk, say): the run stops."""


@dataclass
class _Run:
    """The driver's state: the objects still to do, and how often each killed its worker."""

    todo: dict[str, Path]
    crashes: dict[str, int] = field(default_factory=dict)


def run_dataset(inputs: Sequence[str | Path], out: str | Path, job: Job | LabelJob = Job(), *,
                executor: Executor | None = None, workers: int | None = None,
                retry_failed: bool = False, progress: bool | None = None,
                log: Callable[[str], object] | None = None,
                progress_every: float | None = None) -> Summary:
    """Run ``job`` on every object of ``inputs``, writing results to ``out``; resumable.

    Parameters
    ----------
    inputs : sequence of str or Path
        Files, folders and glob patterns (:func:`expand_inputs`).
    out : str or Path
        The results folder (created). Re-running with the same job resumes.
        Locked while the run lasts: a second run on it is refused.
    job : Job or forceclosure.app.dataset_gripper.GripperJob
        Regions (synthesis, analysis) or labelled parallel-jaw grasps.
    executor : concurrent.futures.Executor, optional
        Where the objects are computed, e.g. a Dask ``Client.get_executor()``.
        Its workers must see the input files at the same paths. Default: a
        local process pool of ``workers`` processes (all cores); with
        ``workers=1`` and no time limit everything runs in this process.
    retry_failed : bool
        Compute failed and timed-out objects again.
    progress : bool, optional
        True: a progress bar; False: no progress; default: a bar when
        standard error is a terminal, else a progress line
        (:class:`forceclosure.app.progress.ProgressLines`: done/total, rate,
        time left) every ``progress_every`` seconds.
    log : callable, optional
        Called with a line per failure or warning, per worker compiling the
        kernels, and the progress lines (default: written above the progress
        bar, on standard error).
    progress_every : float, optional
        Seconds between progress lines (0: one per object; default:
        ``FORCECLOSURE_PROGRESS_SECONDS``, else 10).

    Returns
    -------
    Summary

    Raises
    ------
    InputError
        Bad options, ``out`` in use by another run or holding another job's
        results, or ``out`` not writable (a full disk: the records written
        so far are kept).

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
    require("pyarrow.parquet", "the dataset's table", "table")  # refused before any work
    # never its own job.json, records, tables, pictures and exports
    paths = expand_inputs(inputs, exclude=out, folders=getattr(job, "output_folders", list)())
    if job.mode == "synthesize":  # a hand no object can serve: refuse before any work
        from ..synthesis.best import check_hand

        for dim in _dims(paths):
            check_hand(dim, job.fingers, job.contact, job.mu, top=job.top,
                       construction=job.construction, method=job.method)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: is a file, not a folder")
    folder = out / "objects"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise InputError(f"--out {out}: cannot create it ({e.strerror})") from None
    with locked(out):
        remove_temporaries([out, folder])
        try:
            _check_job(out, job, log)
        except OSError as e:
            raise InputError(f"--out {out}: cannot write job.json ({e.strerror})") from None
        return _run_locked(paths, out, job, executor, workers, retry_failed, progress, log,
                           progress_every)


def _terminal() -> bool:
    """Whether standard error is a terminal (a progress bar's place)."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def _run_locked(paths: list[Path], out: Path, job: Job | LabelJob, executor: Executor | None,
                workers: int | None, retry_failed: bool, progress: bool | None,
                log: Callable[[str], object] | None,
                progress_every: float | None = None) -> Summary:
    from tqdm import tqdm

    folder = out / "objects"
    names = {record_name(p): p for p in paths}
    every = every_from_environment() if progress_every is None else float(progress_every)
    if not every >= 0:
        raise InputError(f"progress_every must be a number of seconds >= 0, got {every!r}")
    lines_wanted = progress is None and not _terminal()   # piped: lines instead of a bar
    size = bar_size()  # none: the terminal's own, followed as it changes
    bar = tqdm(total=0, unit="obj", desc="objects", file=sys.stderr,
               disable=not progress if progress is not None else None,
               dynamic_ncols=not size, **size)
    write = log or (lambda line: bar.write(line, file=sys.stderr))

    def say(line: str) -> None:
        write(printable(line))
    identity = job.identity()
    stamps = {n: fingerprint(p, job) for n, p in names.items()}
    held = _held(folder, names, identity, stamps, say, getattr(job, "check", None), job)
    keep = {"done"} if retry_failed else set(STATUSES)
    run = _Run({n: p for n, p in names.items()
                if n not in held or held[n].get("status") not in keep})
    skipped = len(names) - len(run.todo)
    records = {n: held[n] for n in names if n in held}
    workers = workers or os.cpu_count() or 1
    start = time.perf_counter()
    computed, interrupted = 0, False
    failure: OSError | None = None
    bar.reset(total=len(run.todo))
    ticker = ProgressLines(len(run.todo), say, every=every) if lines_wanted else None

    def finish(name: str, record: dict[str, Any]) -> None:
        nonlocal computed
        record = {**record, "job": identity, "input": stamps[name]}
        try:
            if hasattr(job, "store"):  # files beside the record (gripper: labels), first
                record = job.store(folder, name, record)
            write_atomically(folder / name, json.dumps(record) + "\n")
        except OSError as e:
            raise _OutputFailed(e) from e
        records[name] = record
        run.todo.pop(name, None)
        computed += 1
        bar.update(1)
        if ticker is not None:
            ticker.update(1)
        if record["status"] != "done":
            say(f"forceclosure: {record['status']}: {record['error']}")

    table: OSError | None = None
    try:
        if executor is None and workers == 1 and job.timeout is None:
            from ..kernels import on_compiling

            before = on_compiling(say)  # this process compiles: said above the bar
            try:
                for name, path in list(run.todo.items()):
                    finish(name, process_object(path, job))
            finally:
                on_compiling(before)
        elif executor is None:
            _local_pool(workers, run, job, finish, say)
        else:
            _drain(executor, run, job, finish, say)
    except KeyboardInterrupt:
        interrupted = True
    except _OutputFailed as e:
        failure = e.args[0]
    finally:
        bar.close()
        try:
            with holding():  # Ctrl-C on the command line waits for the tables (app/interrupt)
                write_table(out, records.values())
                if hasattr(job, "write_tables"):  # tables of its own (gripper: grasps.parquet)
                    job.write_tables(out, records.values())
        except OSError as e:
            table = e
    error = failure or table
    if error is not None:
        kept = (f"the {len(records)} records written are kept"
                + ("" if table is None else "; results.parquet is not updated"))
        raise InputError(f"--out {out}: cannot write ({error.strerror or error}): {kept}; "
                         "make room and run the same command again to resume")
    statuses = [r.get("status") for r in records.values()]
    return Summary(objects=len(names), done=statuses.count("done"),
                   failed=statuses.count("failed"), timeout=statuses.count("timeout"),
                   computed=computed, skipped=skipped,
                   seconds=time.perf_counter() - start, workers=workers, out=out,
                   interrupted=interrupted,
                   incomplete=sum(r.get("status") == "done"
                                  and isinstance(r.get("undecided"), int) and r["undecided"] > 0
                                  for r in records.values()))


def _failed(path: Path, error: str, status: str = "failed") -> dict[str, Any]:
    return {"path": _key(path), "name": path.stem, "status": status, "error": error,
            "seconds": None}


def _on_executor(path: Path, job: Job | LabelJob) -> dict[str, Any]:
    """:func:`process_object` on an executor's worker; a Dask worker first arranges to tell
    the run when it compiles the kernels (:func:`forceclosure.app.workers.tell_dask_run`)."""
    tell_dask_run()
    return process_object(path, job)


def _drain(executor: Executor, run: _Run, job: Job | LabelJob,
           finish: Callable[[str, dict[str, Any]], None],
           say: Callable[[str], object] | None = None) -> None:
    """Submit every pending object to ``executor`` and finish each as its result arrives.

    An object whose future fails (Dask's KilledWorker, after the scheduler's
    own retries) is recorded as failed. On a Dask executor, what its workers
    tell the run (compiling the kernels) is said with ``say``.
    """
    client = getattr(executor, "_client", None)  # Dask's Client.get_executor()
    if say is None or client is None or not callable(getattr(client, "subscribe_topic", None)):
        _drain_futures(executor, run, job, finish)  # nothing to listen to, or no one to tell
        return
    from .workers import TOPIC

    with suppress(Exception):
        client.subscribe_topic(TOPIC, lambda event: say(str(event[1])))
    try:
        _drain_futures(executor, run, job, finish)
    finally:
        with suppress(Exception):
            client.unsubscribe_topic(TOPIC)


def _drain_futures(executor: Executor, run: _Run, job: Job | LabelJob,
                   finish: Callable[[str, dict[str, Any]], None]) -> None:
    futures: dict[Future, str] = {executor.submit(_on_executor, run.todo[n], job): n
                                  for n in run.todo}
    for future in as_completed(futures):
        name = futures[future]
        try:
            record = future.result()
        except Exception as e:  # the executor lost the object (e.g. KilledWorker)
            why = str(e).splitlines()[0] if str(e) else ""
            finish(name, _failed(run.todo[name], f"{run.todo[name].name}: its worker died "
                                                 f"({type(e).__name__}: {why})"))
            continue
        finish(name, record)


def _context() -> multiprocessing.context.BaseContext:
    """Workers forked from a clean server process: forking this one is unsafe once its
    compiled kernels have started OpenMP threads."""
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["forceclosure.app.dataset", "forceclosure.synthesis"])
    return context


def _worker_init(job: Job | LabelJob, dims: tuple[int, ...] = (2, 3), notices: Any = None,
                 counter: Any = None) -> None:
    """A pool worker: dies with the run; its kernels run on one thread (the pool already
    uses every core); and they are loaded before its first object, whose time limit would
    otherwise pay for it (seconds: a fresh worker, the one replacing a killed worker too,
    timed out its first object under a short limit). If that compiles them, it tells the
    run so on ``notices`` (a queue), naming itself by ``counter``'s next number."""
    import numba

    die_with_run()
    _process_local_numba_lock()
    numba.set_num_threads(1)
    if notices is not None:
        notices.cancel_join_thread()  # a line not yet sent never holds up the worker's end
        who = f"worker {number_worker(counter)}" if counter is not None else (
            f"worker {os.getpid()}")
        tell_compiling(notices.put, who)
    _warm_up(job, dims)


def _process_local_numba_lock() -> None:
    """In a pool worker, before numba starts its threads: give numba's threading-layer
    start-up a lock of this process only.

    Numba takes a multiprocessing ``RLock`` for that start-up when the start
    method's name contains "fork" -- "forkserver" does -- a named semaphore
    registered with the run's ``resource_tracker`` and unregistered only by
    the worker's exit handlers. A worker the pool ends (a time limit, or its
    ``stop`` at the end of the run) runs none, and the tracker then printed
    "There appear to be 1 leaked semaphore objects to clean up at shutdown"
    on the run's standard error. The lock only guards a start-up inside this
    process (a worker starts no processes), so a thread lock does its work.
    """
    with suppress(Exception):  # numba's private module state; without it, the old way
        from numba.np.ufunc import parallel

        if getattr(parallel, "_backend_init_process_lock", False) is None:
            # numba's module types it None (its first value); it holds a lock once set
            parallel._backend_init_process_lock = threading.RLock()  # type: ignore[assignment]


def _warm_up(job: Job | LabelJob, dims: tuple[int, ...]) -> None:
    """Run the job's compiled kernels once on small bundled objects of the dimensions
    ``dims`` (errors ignored)."""
    from dataclasses import replace

    with suppress(Exception):
        if job.mode == "gripper":
            job.warm_up()
            return
        if job.mode == "synthesize":
            small = replace(job, samples=min(job.samples, 200), top=1, timeout=None)
            for name in [("square", "cube")[d - 2] for d in dims]:
                process_object(name, small)
            return
        from ..analysis.batch import analyze_batch, epsilon_batch

        pinches = {2: (np.array([[[-1.0, 0.0], [1.0, 0.1]]]),
                       np.array([[[-1.0, 0.0], [1.0, 0.0]]])),
                   3: (np.array([[[-1.0, 0, 0], [1, 0.1, 0], [0, 1, 0]]]),
                       np.array([[[-1.0, 0, 0], [1, 0, 0], [0, 1, 0]]]))}
        for P, N in (pinches[d] for d in dims):
            closed = analyze_batch(P, N, mu=0.5)
            if len(closed.code):
                epsilon_batch(P, N, mu=0.5)


def _dims(paths: Iterable[Path]) -> tuple[int, ...]:
    """The dimensions of the objects at ``paths``, as their names tell (polygon files and
    bundled polygons are planar)."""
    from ..objects import POLYGONS

    return tuple(sorted({2 if p.suffix.lower() in POLYGON_SUFFIXES or str(p) in POLYGONS
                         else 3 for p in paths}))


def _local_pool(workers: int, run: _Run, job: Job | LabelJob,
                finish: Callable[[str, dict[str, Any]], None],
                say: Callable[[str], object]) -> None:
    """Everything on a local pool of killable worker processes (pebble's ``ProcessPool``).

    Each object's time limit is enforced twice: in its worker, by
    :func:`deadline` (between bytecodes, leaving the worker alive), and by
    the pool, which kills the worker :data:`HARD_GRACE` seconds later (inside
    compiled code). An object whose worker dies is run again on a fresh one;
    after :data:`MAX_CRASHES` deaths it is recorded as failed.
    """
    from pebble import ProcessExpired, ProcessPool
    from pebble.common import CONSTS

    # pebble stops a worker over its time limit with SIGTERM, then waits this long before
    # SIGKILL, holding the lock all workers need to hand in results: a worker stuck in
    # compiled code (deaf to SIGTERM) stalled the whole pool 3 s, and pushed others over
    # their limits. Our workers have nothing to clean up.
    CONSTS.term_timeout = min(CONSTS.term_timeout, 0.2)
    hard = None if job.timeout is None else job.timeout + HARD_GRACE
    context = _context()
    notices, counter = context.Queue(), context.Value("i", 0)
    relay = Relay(notices, say)
    relay.start()
    pool = ProcessPool(workers, context=context, initializer=_worker_init,
                       initargs=(job, _dims(run.todo.values()), notices, counter))
    arrived: queue.SimpleQueue[tuple[str, Future]] = queue.SimpleQueue()
    pending = 0

    def submit(name: str) -> None:
        nonlocal pending
        future = pool.schedule(process_object, (run.todo[name], job), timeout=hard)
        pending += 1
        future.add_done_callback(lambda f: arrived.put((name, f)))  # name: this call's

    watchdog = Watchdog(STALL_SECONDS, say)
    watchdog.start()
    try:
        for name in list(run.todo):
            submit(name)
        while pending:
            try:  # in slices: Ctrl-C, raised in this thread (app/interrupt), lands at once
                name, future = arrived.get(timeout=0.2)
            except queue.Empty:
                continue
            pending -= 1
            path = run.todo[name]
            try:
                record = future.result()
            except FutureTimeout:
                record = _failed(path, f"{path.name}: over the time limit of {job.timeout:g} s "
                                       "(its worker did not stop, and was killed)", "timeout")
            except ProcessExpired as e:
                run.crashes[name] = run.crashes.get(name, 0) + 1
                if run.crashes[name] < MAX_CRASHES:
                    submit(name)
                    continue
                why = (f"killed by signal {-e.exitcode}" if e.exitcode and e.exitcode < 0
                       else f"exit status {e.exitcode}")
                record = _failed(path, f"{path.name}: its worker process died {MAX_CRASHES} "
                                       f"times on it (last: {why}; out of memory?)")
            except Exception as e:  # the pool could not run it (e.g. a broken pool)
                first = str(e).splitlines()[0] if str(e) else ""
                record = _failed(path, f"{path.name}: internal error: {type(e).__name__}: "
                                       f"{first}")
            finish(name, record)
        pool.close()  # all done: the workers end as they would
    finally:
        watchdog.halt.set()
        pool.stop()  # Ctrl-C, a full disk: end the workers now
        pool.join()
        watchdog.join()
        relay.stop()
        notices.close()
