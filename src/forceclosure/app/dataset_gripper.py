"""Datasets of labelled parallel-jaw grasps: ``forceclosure dataset --gripper NAME``.

The gripper job of :func:`forceclosure.app.dataset.run_dataset`: on every
object of a set, :func:`forceclosure.gripper.labels.grasp_labels` samples ``count``
jaw poses the hand (a built-in or the generic one) can take and
labels them (verdict with exact cones, least friction μ*, Ferrari–Canny ε,
gripper–object collision). Everything else is the dataset's machinery:
the worker pool, the time limit, one record per object (stamped with the
job and the input's fingerprint, so an interrupted run resumes and a
changed object is redone) and ``results.parquet`` (one row per object).
This job adds, in ``DIR``,

* ``objects/<name>-<hash>.npz``: the object's labels
  (:meth:`~forceclosure.gripper.labels.GraspLabels.save`), written atomically by
  the driver just before the object's record, which holds the file's
  SHA-256: a record whose labels file is missing or changed is computed
  again;
* ``grasps.parquet``: one row per grasp of every object done
  (:data:`GRASP_COLUMNS`), rebuilt from the ``.npz`` files at the end of
  every run, written atomically.

Each object's sampling seed is :func:`object_seed` of the job's seed and
the object's fingerprint (:func:`forceclosure.app.dataset.fingerprint`: a
SHA-256 of its file and of the meshes a URDF names): distinct objects get
distinct seeds, whatever their order in the set or the other objects in
it, and the seed changes exactly when the object does.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, OutputError
from ..extras import require
from ..verdicts import VERDICT_WORDS, VerdictCode

__all__ = ["GRASP_COLUMNS", "GripperJob", "object_seed", "read_labels", "sha256_of",
           "write_grasp_table"]


def sha256_of(file: Path) -> str:
    """The SHA-256 of a file's bytes, in hex (:func:`forceclosure.io.files.fingerprint`)."""
    from ..io.files import fingerprint

    return fingerprint(str(file)).removeprefix("sha256:")

#: The columns of grasps.parquet, in order: (name, pyarrow type name). ``name`` and ``path``
#: are results.parquet's (join on ``path``); the rest are one grasp of the object's ``.npz``.
GRASP_COLUMNS = (("name", "string"), ("path", "string"), ("grasp", "int64"),
                 *((f"center_{a}", "float64") for a in "xyz"),
                 *((f"closing_axis_{a}", "float64") for a in "xyz"),
                 *((f"approach_axis_{a}", "float64") for a in "xyz"),
                 ("width", "float64"),
                 *((f"{what}{jaw}_{a}", "float64") for jaw in (1, 2)
                   for what in ("point", "normal") for a in "xyz"),
                 ("verdict", "string"), ("least_friction", "float64"), ("epsilon", "float64"),
                 ("collides", "bool"))



def object_seed(seed: int, stamp: str) -> int:
    """The sampling seed of the object whose fingerprint is ``stamp``, in a job seeded
    ``seed``: the first 63 bits of ``SHA-256("<seed>:<stamp>")`` (big-endian).

    Examples
    --------
    >>> import hashlib
    >>> s = object_seed(0, "ab" * 32)
    >>> s == int.from_bytes(hashlib.sha256(("0:" + "ab" * 32).encode()).digest()[:8], "big") >> 1
    True
    >>> object_seed(1, "ab" * 32) != s
    True
    """
    digest = hashlib.sha256(f"{int(seed)}:{stamp}".encode("ascii")).digest()
    return int.from_bytes(digest[:8], "big") >> 1


def _finite_or_none(value: float) -> float | None:
    """A JSON-ready number: None where it is not finite (a median μ* of "no friction closes")."""
    value = float(value)
    return value if np.isfinite(value) else None


@dataclass(frozen=True)
class GripperJob:
    """Sample and label ``count`` parallel-jaw grasps on every object.

    Attributes
    ----------
    width : float or None
        The generic gripper's widest opening (object units); None with a built-in ``hand``.
    mu : float
        Friction coefficient of the labels.
    count : int
        Jaw poses sampled per object.
    contact : {"soft", "hard"}
    pad_radius : float or None
        Soft pads' torsion: None bounded by the hand's pad, ``a`` by a disc of radius ``a``
        ((2/3) μ a), 0 the paper's soft finger (unlimited).
    hand : str
        The gripper: ``"parallel-jaw"`` (the generic one of ``width``) or a built-in
        (:mod:`forceclosure.gripper.grippers`).
    seed : int
        The job's seed; each object's is :func:`object_seed` of it.
    least_friction : bool
        Compute μ* (closed form for soft pads; milliseconds a grasp with a pad radius); False: NaN.
    timeout, allow_open, allow_outside_meshes
        As for :class:`forceclosure.app.dataset.Job`.

    Examples
    --------
    >>> import tempfile
    >>> from forceclosure.app.dataset import run_dataset
    >>> out = tempfile.mkdtemp()
    >>> job = GripperJob(width=3.0, mu=0.5, count=20)
    >>> run_dataset(["cube"], out, job, workers=1, progress=False).done
    1
    >>> import pandas as pd
    >>> len(pd.read_parquet(f"{out}/grasps.parquet"))
    20
    """

    width: float | None
    mu: float
    count: int = 1000
    contact: str = "soft"
    pad_radius: float | None = None
    seed: int = 0
    least_friction: bool = True
    timeout: float | None = None
    allow_open: bool = False
    allow_outside_meshes: bool = False
    hand: str = "parallel-jaw"

    #: The dataset's dispatch key (:func:`forceclosure.app.dataset.process_object`).
    mode = "gripper"

    def __post_init__(self) -> None:
        from ..gripper.grippers import make_gripper

        if self.width is not None and not (math.isfinite(self.width) and self.width > 0):
            raise InputError(f"--width must be a finite positive opening, got {self.width}")
        if not (math.isfinite(self.mu) and self.mu > 0):
            raise InputError(f"--mu must be finite and positive, got {self.mu}")
        if self.count < 1:
            raise InputError(f"--count must be at least 1, got {self.count}")
        if self.contact not in ("soft", "hard"):
            raise InputError(f"--contact {self.contact}: a parallel-jaw gripper has soft or "
                             "hard contacts")
        if self.pad_radius is not None and not (math.isfinite(self.pad_radius)
                                                and 0 <= self.pad_radius <= 1e150):
            raise InputError(f"--pad-radius must be finite and >= 0, got {self.pad_radius}")
        try:
            make_gripper(self.hand, self.width, self.pad_radius)
        except InputError as e:
            raise InputError(f"--gripper {self.hand}: {str(e).replace('width:', '--width:')}"
                             ) from None
        if self.timeout is not None and not self.timeout > 0:
            raise InputError(f"--timeout must be a positive number of seconds, got "
                             f"{self.timeout:g}")
        if self.timeout is not None and math.isinf(self.timeout):
            object.__setattr__(self, "timeout", None)  # inf: no limit

    def identity(self) -> dict[str, Any]:
        """The options that decide the results (the time limit does not)."""
        return {"mode": "gripper", "gripper": self.hand, "width": self.gripper().width_max,
                "mu": float(self.mu), "count": int(self.count), "contact": self.contact,
                "pad_radius": self.pad_radius, "seed": int(self.seed),
                "least_friction": bool(self.least_friction), "collision": True,
                "allow_open": self.allow_open,
                "allow_outside_meshes": self.allow_outside_meshes}

    def gripper(self):
        """The hand (:func:`forceclosure.gripper.grippers.make_gripper`)."""
        from ..gripper.grippers import make_gripper

        return make_gripper(self.hand, self.width, self.pad_radius)

    # -- on a worker ----------------------------------------------------------------------

    def label(self, obj: Any, path: Path) -> dict[str, Any]:
        """The record's fields for one loaded object, and its labels under ``"_labels"``
        (taken out and saved by :meth:`store`, in the driver)."""
        from ..gripper.labels import grasp_labels
        from .dataset import fingerprint

        if obj.dim != 3:
            raise InputError(f"{path.name}: a polygon; a parallel-jaw gripper grasps meshes")
        seed = object_seed(self.seed, fingerprint(path, self))
        labels = grasp_labels(obj, self.gripper(), self.mu, self.count, seed, self.contact,
                              least_friction=self.least_friction)
        closed = labels.epsilon[labels.code == VerdictCode.CLOSURE]
        finite = labels.least_friction[np.isfinite(labels.least_friction)]
        hit = labels.collides
        return {"contact": self.contact, "mu": self.mu, "width": labels.meta["width_max"],
                "pad_radius": self.pad_radius, "seed": seed, "grasps": len(labels),
                **labels.counts(),
                "epsilon_median": float(np.median(closed)) if len(closed) else None,
                "least_friction_median": _finite_or_none(np.median(labels.least_friction))
                if self.least_friction and len(finite) else None,
                "collides": None if hit is None else int(hit.sum()),
                "closure_clear": None if hit is None else int(
                    np.sum(~hit & (labels.code == VerdictCode.CLOSURE))),
                "attempts": int(labels.meta["attempts"]),
                "rejected": int(sum(labels.meta["rejected"].values())),
                "rejected_reasons": dict(labels.meta["rejected"]),
                "_labels": labels}

    def warm_up(self) -> None:
        """Compile the kernels the job uses, on a few grasps of the bundled cube."""
        from ..gripper.jaw import ParallelJaw
        from ..gripper.labels import grasp_labels

        grasp_labels("cube", ParallelJaw(3.0, self.pad_radius), self.mu, 4, 0, self.contact,
                     least_friction=self.least_friction, approaches=1, depths=1)

    # -- in the driver --------------------------------------------------------------------

    def store(self, folder: Path, name: str, record: dict[str, Any]) -> dict[str, Any]:
        """Save the labels a worker returned to ``folder/<record stem>.npz`` (atomically) and
        return the record to write, naming the file and its SHA-256. Raises ``OSError``
        when the file cannot be written."""
        record = dict(record)
        labels = record.pop("_labels", None)
        file = folder / (Path(name).stem + ".npz")
        if labels is None:  # failed, timed out: no labels (an older file is not theirs)
            file.unlink(missing_ok=True)
            return record
        try:
            labels.save(str(file))
        except OutputError as e:
            raise OSError(str(e)) from None
        record["labels_file"] = file.name
        record["labels_sha256"] = sha256_of(file)
        return record

    def check(self, folder: Path, record: dict[str, Any]) -> str | None:
        """Why a held record cannot stand (its labels file missing or changed), or None."""
        if record.get("status") != "done":
            return None
        name, digest = record.get("labels_file"), record.get("labels_sha256")
        if not isinstance(name, str) or not isinstance(digest, str):
            return "fields missing (labels_file, labels_sha256)"
        file = folder / name
        if Path(name).name != name or not file.is_file():
            return f"its labels file {name[:200]!r} is missing"
        if sha256_of(file) != digest:
            return f"its labels file {name[:200]!r} changed since"
        return None

    def write_tables(self, out: Path, records: Iterable[dict[str, Any]]) -> Path:
        """Write ``out/grasps.parquet`` from the done records' labels files."""
        return write_grasp_table(out, records)


def read_labels(file: str | Path) -> dict[str, np.ndarray]:
    """The arrays of a saved labels file (``GraspLabels.save``), ``meta`` left out."""
    with np.load(file, allow_pickle=False) as z:
        return {k: z[k] for k in z.files if k != "meta"}


def _schema() -> Any:
    pa = require("pyarrow", "the dataset's table", "table")

    types = {"string": pa.string(), "float64": pa.float64(), "int64": pa.int64(),
             "bool": pa.bool_()}
    return pa.schema([(name, types[t]) for name, t in GRASP_COLUMNS])


def _grasp_columns(record: dict[str, Any], arrays: dict[str, np.ndarray]) -> dict[str, Any]:
    n = len(arrays["code"])
    columns: dict[str, Any] = {"name": [record.get("name")] * n, "path": [record.get("path")] * n,
                               "grasp": np.arange(n, dtype=np.int64)}
    for key in ("center", "closing_axis", "approach_axis"):
        for i, a in enumerate("xyz"):
            columns[f"{key}_{a}"] = arrays[key][:, i]
    columns["width"] = arrays["width"]
    for jaw in (1, 2):
        for key, what in (("points", "point"), ("normals", "normal")):
            for i, a in enumerate("xyz"):
                columns[f"{what}{jaw}_{a}"] = arrays[key][:, jaw - 1, i]
    columns["verdict"] = np.array(VERDICT_WORDS, dtype=object)[arrays["code"].astype(np.int64)]
    columns["least_friction"] = arrays["least_friction"]
    columns["epsilon"] = arrays["epsilon"]
    columns["collides"] = arrays["collides"] if "collides" in arrays else [None] * n
    return columns


def write_grasp_table(out: str | Path, records: Iterable[dict[str, Any]]) -> Path:
    """Write ``out/grasps.parquet`` (atomically): one row per grasp (:data:`GRASP_COLUMNS`)
    of every done record's labels file, objects in the order of their paths, grasps in the
    order of the file."""
    from ..io.outdir import atomic_file

    pa = require("pyarrow", "the dataset's table", "table")
    pq = require("pyarrow.parquet", "the dataset's table", "table")

    out = Path(out)
    schema = _schema()
    done = sorted((r for r in records if r.get("status") == "done" and r.get("labels_file")),
                  key=lambda r: str(r.get("path") or ""))
    path = out / "grasps.parquet"
    with atomic_file(path) as f, pq.ParquetWriter(f, schema) as writer:
        for record in done:
            arrays = read_labels(out / "objects" / record["labels_file"])
            writer.write_table(pa.table(_grasp_columns(record, arrays), schema=schema))
    return path
