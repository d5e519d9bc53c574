"""A dataset's results folder: ``job.json`` (the job its results belong to), one record per
object under ``objects/`` (kept only while it stands for its object in this job), and the
``results.parquet`` table rebuilt from them."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from ..errors import InputError, printable
from ..extras import require
from ..files.outdir import atomic_file, write_atomically
from .inputs import object_key
from .job import Job, LabelJob

__all__ = ["COLUMNS", "STATUSES", "WARNED", "check_job", "comparable", "held_records",
           "row_of", "write_table"]

STATUSES = ("done", "failed", "timeout")
#: Damaged, foreign or stale records warned about one by one; the rest are counted.
WARNED = 20


def _jobs_of_records(folder: Path, job: Any = None) -> list[dict[str, Any]]:
    """The distinct jobs (as :func:`comparable` to ``job``) the readable records in
    ``folder`` say they belong to."""
    jobs: dict[str, dict[str, Any]] = {}
    for file in sorted(folder.glob("*.json")) if folder.is_dir() else []:
        try:
            record = json.loads(file.read_text(encoding="utf-8"))
        except (OSError, ValueError, UnicodeDecodeError, RecursionError):
            continue
        if isinstance(record, dict) and isinstance(record.get("job"), dict):
            jobs.setdefault(json.dumps(comparable(record["job"], job), sort_keys=True),
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
    job : Job or forceclosure.datasets.gripper_job.GripperJob
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


def comparable(stored: dict[str, Any], job: Any) -> dict[str, Any]:
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


def check_job(out: Path, job: Job | LabelJob, warn: Callable[[str], object] | None = None) -> None:
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
        same = comparable(wanted, job)
        if isinstance(held, dict):
            held = comparable(held, job)
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
           # gripper (forceclosure.datasets.gripper_job; also grasps, contact, mu, closure,
           # marginal, none and epsilon_median above)
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


def arrow_table(records: Iterable[dict[str, Any]]) -> Any:
    pa = require("pyarrow", "the dataset's table", "table")

    types = {"string": pa.string(), "float64": pa.float64(), "int64": pa.int64(),
             "bool": pa.bool_(), "list<float64>": pa.list_(pa.float64())}
    schema = pa.schema([(name, types[t]) for name, t in COLUMNS])
    rows = sorted((row_of(r) for r in records), key=lambda r: (r["path"] or ""))
    return pa.Table.from_pylist(rows, schema=schema)


def write_table(out: Path, records: Iterable[dict[str, Any]]) -> Path:
    """Write ``out/results.parquet`` (atomically) from object records."""
    pq = require("pyarrow.parquet", "the dataset's table", "table")
    table = arrow_table(records)
    path = out / "results.parquet"
    with atomic_file(path) as f:
        pq.write_table(table, f)
    return path


def _damage(record: Any, path: Path, identity: dict[str, Any], stamp: str,
            job: Any = None) -> str | None:
    """Why a record held in ``DIR`` cannot stand for the object at ``path`` in this job, or
    None when it can (its job compared as ``job.json``'s: :func:`comparable`)."""
    if not isinstance(record, dict):
        return f"not a record (a JSON {type(record).__name__})"
    missing = [k for k in ("path", "name", "status", "error", "job", "input")
               if k not in record]
    if missing:
        if missing == ["job", "input"]:
            return "written by an older forceclosure (no job and input stamps)"
        return f"fields missing ({', '.join(missing)})"
    if record["path"] != object_key(path):
        return f"the record of another object ({str(record['path'])[:200]!r})"
    if record["status"] not in STATUSES:
        return f"unknown status {str(record['status'])[:40]!r}"
    if comparable(record["job"], job) != comparable(identity, job):
        return "made by another job (other options)"
    if record["input"] != stamp:
        return "its input changed since (object, meshes or grasp file)"
    try:
        arrow_table([record])
    except Exception as e:  # a field of the wrong type: the Parquet build would fail
        return f"a field of the wrong type ({type(e).__name__})"
    return None


def held_records(folder: Path, names: dict[str, Path], identity: dict[str, Any],
          stamps: dict[str, str], say: Callable[[str], object],
          check: Callable[[Path, dict[str, Any]], str | None] | None = None,
          job: Any = None) -> dict[str, dict[str, Any]]:
    """The records in ``folder`` that stand for their objects; the others are warned about
    (the first :data:`WARNED` one by one, then counted) and will be computed again."""
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
        if bad <= WARNED:
            say(f"forceclosure: warning: {file}: {why}; computing it again")
    if bad > WARNED:
        say(f"forceclosure: warning: {bad - WARNED} more records damaged, foreign or stale; "
            "computing them again")
    return held

