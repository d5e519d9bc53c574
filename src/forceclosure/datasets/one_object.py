"""One object of a dataset, on whatever worker runs it: load it, run the job, and return its
record -- never raising for a bad object."""

from __future__ import annotations

import os
import socket
import time
from contextlib import suppress
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..verdicts import ERROR, Verdict, closed_median, verdict_counts
from .inputs import grasp_file_of, object_key
from .job import Job, LabelJob
from .time_limit import ObjectTimeout, deadline, timed_out

__all__ = ["SURFACE_RTOL", "failed_record", "process_object", "surface_distance"]

#: Contacts farther than this (relative to the object's size) are off its surface.
SURFACE_RTOL = 1e-3


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
    # complete: nothing the hand can do is missing; undecided: sites whose regions could
    # not be proved (grasps may be missing there), as synthesize --json says
    return result.to_dict()


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
        verdicts = results.code.tolist()
        errors = results.errors
        eps_median = closed_median(results.epsilon, results.code)
        per_grasp: list[Any] = []
    else:
        grasp_file = parse_grasp_file(source.read_text(encoding="utf-8"), source.name)
        per_grasp = [result_record(entry, grasp_file.cone)[0] for entry in grasp_file.grasps]
        names = {v.value: int(v.code) for v in Verdict}
        verdicts = [names.get(r.get("verdict"), ERROR) for r in per_grasp]
        counts = verdict_counts(verdicts, errors=True)
        errors = [r["error"] for r in per_grasp if "error" in r]
        eps_median = closed_median([np.nan if r.get("epsilon") is None else r["epsilon"]
                                    for r in per_grasp], verdicts)
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
    record: dict[str, Any] = {"path": object_key(path), "name": path.stem, "status": "done",
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
            if job.mode == "gripper":  # forceclosure.datasets.gripper_job.GripperJob
                record.update(job.label(obj, path))
            else:
                record.update(_synthesize(obj, job) if job.mode == "synthesize"
                              else _analyze(obj, path, job))
    except InputError as e:
        record.update(status="failed", error=str(e))
    except MemoryError:
        record.update(status="failed", error=f"{path.name}: out of memory")
    except (ObjectTimeout, Exception) as e:
        if timed_out(e):
            record.update(status="timeout", error=f"{path.name}: over the time limit of "
                                                  f"{job.timeout:g} s")
        else:  # an internal error: one line, and the run goes on
            first = str(e).splitlines()[0] if str(e) else ""
            record.update(status="failed", error=f"{path.name}: internal error: "
                                                 f"{type(e).__name__}: {first}")
    record["seconds"] = time.perf_counter() - start
    return record


def failed_record(path: Path, error: str, status: str = "failed") -> dict[str, Any]:
    """The record of an object its worker could not finish (killed, lost, over its limit)."""
    return {"path": object_key(path), "name": path.stem, "status": status, "error": error,
            "seconds": None}
