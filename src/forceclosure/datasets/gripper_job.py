"""Datasets of labelled parallel-jaw grasps: ``forceclosure dataset --gripper NAME``.

The gripper job of :func:`forceclosure.datasets.run.run_dataset`: on every
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
the object's fingerprint (:func:`forceclosure.datasets.inputs.fingerprint`: a
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
from typing import Any, ClassVar, Literal

import numpy as np

from ..errors import InputError, OutputError
from ..extras import require
from ..verdicts import VERDICT_WORDS
from .inputs import EXPORTS_FILE

__all__ = ["EXPORTS_FILE", "GRASP_COLUMNS", "GripperJob", "export_dataset", "labels_problem",
           "object_seed", "read_labels", "read_records", "sha256_of", "write_exports",
           "write_grasp_table", "write_pictures"]


def sha256_of(file: Path) -> str:
    """The SHA-256 of a file's bytes, in hex (:func:`forceclosure.files.read.fingerprint`)."""
    from ..files.read import fingerprint

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
        The gripper: ``"parallel-jaw"`` (the generic one of ``width``), a built-in
        (:mod:`forceclosure.gripper.grippers`) or a hand's ``.urdf`` file (kept as its
        absolute path; the hand's sizes are part of the job's identity, whatever the hand).
    seed : int
        The job's seed; each object's is :func:`object_seed` of it.
    least_friction : bool
        Compute μ* (closed form for soft pads; milliseconds a grasp with a pad radius); False: NaN.
    timeout, allow_open, allow_outside_meshes
        As for :class:`forceclosure.datasets.job.Job`.
    collision, clearance, approaches, depths, tilt, epsilon
        As ``forceclosure grasps`` takes them (``--no-collision``, ``--clearance``,
        ``--approaches``, ``--depths``, ``--tilt``, ``--no-epsilon``;
        :func:`forceclosure.gripper.labels.grasp_labels`): the collision check and the
        search of the approach and depth (None: the defaults, 12 approaches and 3
        depths), the closing lines' tilt, and the Ferrari–Canny ε (False: NaN).
    robust : dict, optional
        ``grasps --robust``'s settings (``samples``, ``pose_sigma``, ``angle_sigma``,
        ``mu_sigma``, ``normal_sigma``, ``confidence``, ``epsilon``): the labels get the
        ``robust_*`` arrays (:func:`forceclosure.gripper.robust.robust_labels`, seeded by
        the object's seed).
    metrics : bool
        ``grasps --metrics``: the grasp-matrix metrics' arrays too.
    task : dict, optional
        ``grasps --task-mass``'s settings (``mass``, ``gravity``, ``f_max``, ``edges``): the
        task arrays against the object's weight at its mesh's centre of mass.
    exports : tuple of (kind, folder)
        ``--export KIND FOLDER``: each object's labels also as ``FOLDER/<stem>.npy``
        (``graspnet``) or ``.h5`` (``acronym``), written after every run from the records
        done (:func:`export_dataset`).
    graspnet_score : {"friction", "epsilon"}
        The GraspGroup score of the ``graspnet`` exports.
    hand_links : str, optional
        ``--gripper-links``: a URDF hand's palm and finger links
        (:func:`forceclosure.gripper.grippers.parse_links`).
    support_plane : bool
        ``grasps --support-plane``: each object rests on a table in its most stable pose,
        which the hand must not cross (:mod:`forceclosure.gripper.support`).
    plot, html, plot_top
        ``--plot FOLDER``, ``--html FOLDER``, ``--plot-top K``: each object's ``K`` best
        poses drawn as ``FOLDER/<stem>.png`` (``grasps --plot``'s picture) and
        ``FOLDER/<stem>.html`` (``grasps --html``'s page), after every run
        (:func:`write_pictures`).

    Every option that decides the results or the files is in :meth:`identity`, the job
    file's content: a resumed run must ask for the same ones.

    Examples
    --------
    >>> import tempfile
    >>> from forceclosure.datasets import run_dataset
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
    collision: bool = True
    clearance: float | None = None
    approaches: int | None = None
    depths: int | None = None
    tilt: float = 0.0
    epsilon: bool = True
    robust: dict[str, Any] | None = None
    metrics: bool = False
    task: dict[str, Any] | None = None
    exports: tuple[tuple[str, str], ...] = ()
    graspnet_score: str = "friction"
    plot: str | None = None
    html: str | None = None
    plot_top: int = 10
    support_plane: bool = False
    hand_links: str | None = None

    #: What a job file written before these options existed means by their absence (the
    #: defaults then, and now): :func:`forceclosure.datasets.records.check_job` fills them in.
    IDENTITY_DEFAULTS: ClassVar[dict[str, Any]] = {
        "clearance": None, "approaches": 12, "depths": 3, "tilt": 0.0, "epsilon": True,
        "robust": None, "metrics": False, "task": None, "exports": [],
        "graspnet_score": "friction", "plot": None, "html": None, "plot_top": 10,
        "support_plane": False, "hand_links": None}

    #: The options that only choose the outputs redrawn at the end of every run (pictures,
    #: exports): recorded in job.json, but a resumed run may change them
    #: (:func:`forceclosure.datasets.records.comparable`).
    OUTPUT_OPTIONS: ClassVar[tuple[str, ...]] = ("exports", "graspnet_score", "plot", "html",
                                                 "plot_top")

    #: The dataset's dispatch key (:func:`forceclosure.datasets.one_object.process_object`).
    mode: ClassVar[Literal["gripper"]] = "gripper"

    def __post_init__(self) -> None:
        import os

        from ..gripper.urdf_hand import is_urdf_name

        if isinstance(self.hand, str) and is_urdf_name(self.hand):  # as workers elsewhere
            object.__setattr__(self, "hand", os.path.abspath(self.hand))  # find it, one spelling
        if self.width is not None and not (math.isfinite(self.width) and self.width > 0):
            raise InputError(f"--width must be a finite positive opening, got {self.width}")
        if not (math.isfinite(self.mu) and self.mu > 0):
            raise InputError(f"--mu must be finite and positive, got {self.mu}")
        if self.count < 1:
            raise InputError(f"--count must be at least 1, got {self.count}")
        from ..gripper.jaw import JAW_CONTACTS

        if self.contact not in JAW_CONTACTS:
            raise InputError(f"--contact {self.contact}: a parallel-jaw gripper has soft or "
                             "hard contacts")
        if self.pad_radius is not None and not (math.isfinite(self.pad_radius)
                                                and 0 <= self.pad_radius <= 1e150):
            raise InputError(f"--pad-radius must be finite and >= 0, got {self.pad_radius}")
        try:
            self.gripper()
        except InputError as e:
            text = str(e).replace("width:", "--width:")
            if text.startswith("links"):
                text = "--gripper-links" + text[len("links"):]
            raise InputError(f"--gripper {self.hand}: {text}") from None
        self._check_grasps_options()
        if self.robust is not None and self.robust.get("pose_sigma") is None:  # as grasps
            object.__setattr__(self, "robust", {**self.robust, "pose_sigma": round(
                0.01 * self.gripper().width_max, 15)})
        if self.timeout is not None and not self.timeout > 0:
            raise InputError(f"--timeout must be a positive number of seconds, got "
                             f"{self.timeout:g}")
        if self.timeout is not None and math.isinf(self.timeout):
            object.__setattr__(self, "timeout", None)  # inf: no limit

    def _check_grasps_options(self) -> None:
        """Refuse, in ``grasps``'s words, what ``grasps`` refuses of the same options."""
        from ..io.export import KINDS

        if self.clearance is not None:
            if not (math.isfinite(self.clearance) and self.clearance >= 0):
                raise InputError(f"--clearance must be finite and >= 0, got {self.clearance}")
            if not self.collision:
                raise InputError("--clearance is the collision check's; it has no use with "
                                 "--no-collision")
        for flag, value in (("--approaches", self.approaches), ("--depths", self.depths)):
            if value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise InputError(f"{flag} must be a whole number >= 1, got {value}")
            if not self.collision:
                raise InputError(f"{flag} is searched by the collision check; it has no use "
                                 "with --no-collision")
        if self.support_plane and not self.collision:
            raise InputError("--support-plane is part of the collision check; it has no use "
                             "with --no-collision")
        if not (isinstance(self.tilt, (int, float)) and 0 <= self.tilt <= 1):
            raise InputError(f"--tilt must be a share from 0 to 1, got {self.tilt}")
        if self.graspnet_score not in ("friction", "epsilon"):
            raise InputError(f"--graspnet-score must be friction or epsilon, got "
                             f"{self.graspnet_score!r}")
        if not self.epsilon and self.graspnet_score == "epsilon":
            raise InputError("--graspnet-score epsilon needs the epsilon: drop --no-epsilon")
        if self.task is not None and not {"mass", "gravity", "f_max", "edges"} <= set(self.task):
            raise InputError("task: needs mass, gravity, f_max and edges")
        if self.robust is not None and not {
                "samples", "pose_sigma", "angle_sigma", "mu_sigma", "normal_sigma",
                "confidence", "epsilon"} <= set(self.robust):
            raise InputError("robust: needs samples, pose_sigma, angle_sigma, mu_sigma, "
                             "normal_sigma, confidence and epsilon")
        object.__setattr__(self, "exports", tuple((str(k), str(f)) for k, f in self.exports))
        for kind, _ in self.exports:
            if kind not in KINDS:
                raise InputError(f"--export: unknown kind {kind!r}; the kinds are "
                                 + ", ".join(KINDS))
            if (kind == "graspnet" and self.graspnet_score == "friction"
                    and not self.least_friction):
                raise InputError("--export graspnet: the friction score needs the least "
                                 "friction; drop --no-least-friction or pass --graspnet-score "
                                 "epsilon")
        if isinstance(self.plot_top, bool) or not isinstance(self.plot_top, int) or (
                self.plot_top < 0):
            raise InputError(f"--plot-top must be a whole number >= 0, got {self.plot_top}")
        for flag, folder in [("--plot", self.plot), ("--html", self.html),
                             *((f"--export {k}", f) for k, f in self.exports)]:
            if folder is not None and not str(folder).strip():
                raise InputError(f"{flag} is empty: give a folder name")
        if self.html:  # before any work, as synthesize --html
            require("plotly", "the interactive HTML view", "view")
        folders = [f for _, f in self.exports] + [f for f in (self.plot, self.html) if f]
        if len(set(folders)) < len(folders):
            raise InputError("--export, --plot and --html: each needs its own folder")
        for flag, folder in (("--plot", self.plot), ("--html", self.html)):
            if folder and Path(folder).exists() and not Path(folder).is_dir():
                raise InputError(f"{flag} {folder}: a dataset's pictures go in a folder (this "
                                 "is a file)")
        if len({f for _, f in self.exports}) < len(self.exports):
            raise InputError("--export: each kind needs its own folder")
        for kind, folder in self.exports:
            if Path(folder).exists() and not Path(folder).is_dir():
                raise InputError(f"--export {kind} {folder}: a dataset's exports go in a "
                                 "folder (this is a file)")
            if kind == "acronym":
                from ..io.export import require_h5py

                require_h5py()

    def output_folders(self) -> list[str]:
        """The folders this job writes besides the dataset's own: its exports and pictures
        (never read as objects: :func:`forceclosure.datasets.inputs.expand_inputs`)."""
        return [f for _, f in self.exports] + [f for f in (self.plot, self.html) if f]

    def _search(self) -> tuple[int | None, int | None]:
        """The approaches and depths searched (None without the collision check)."""
        from ..gripper.hand_poses import APPROACHES, DEPTHS

        if not self.collision:
            return None, None
        return (APPROACHES if self.approaches is None else int(self.approaches),
                DEPTHS if self.depths is None else int(self.depths))

    def identity(self) -> dict[str, Any]:
        """The options that decide the results and the files written (the time limit does
        not)."""
        approaches, depths = self._search()
        return {"mode": "gripper", "gripper": self.hand, "width": self.gripper().width_max,
                "mu": float(self.mu), "count": int(self.count), "contact": self.contact,
                "pad_radius": self.pad_radius, "seed": int(self.seed),
                "least_friction": bool(self.least_friction), "collision": bool(self.collision),
                "allow_open": self.allow_open,
                "allow_outside_meshes": self.allow_outside_meshes,
                "clearance": self.clearance, "approaches": approaches, "depths": depths,
                "tilt": float(self.tilt), "epsilon": bool(self.epsilon),
                "robust": None if self.robust is None else dict(self.robust),
                "metrics": bool(self.metrics),
                "task": None if self.task is None else dict(self.task),
                "exports": [list(e) for e in self.exports],
                "graspnet_score": self.graspnet_score, "plot": self.plot, "html": self.html,
                "plot_top": int(self.plot_top), "support_plane": bool(self.support_plane),
                "hand_links": self.hand_links,
                **self._hand_identity()}

    def _hand_identity(self) -> dict[str, Any]:
        """The hand's sizes, whatever the hand (a URDF file, a built-in, the generic one): a
        changed file, or a built-in whose sizes changed since, is another job."""
        return {"hand": self.gripper().shape()}

    def gripper(self):
        """The hand (:func:`forceclosure.gripper.grippers.make_gripper`)."""
        from ..gripper.grippers import make_gripper

        return make_gripper(self.hand, self.width, self.pad_radius, self.hand_links,
                            allow_outside_meshes=self.allow_outside_meshes)

    # -- on a worker ----------------------------------------------------------------------

    def label(self, obj: Any, path: Path) -> dict[str, Any]:
        """The record's fields for one loaded object, and its labels under ``"_labels"``
        (taken out and saved by :meth:`store`, in the driver)."""
        from ..analysis.task import TASK_VERDICTS
        from ..gripper.pipeline import label_poses
        from .inputs import fingerprint

        if obj.dim != 3:
            raise InputError(f"{path.name}: a polygon; a parallel-jaw gripper grasps meshes")
        if self.task is not None and getattr(obj, "watertight", True) is False:
            raise InputError(f"{path.name}: --task-mass needs a closed mesh for its centre "
                             "of mass; this one is open")
        seed = object_seed(self.seed, fingerprint(path, self))
        approaches, depths = self._search()
        support = None
        if self.support_plane:
            from ..gripper.support import support_plane

            support = support_plane(obj)
        found = label_poses(obj, self.gripper(), self.mu, self.count, seed, self.contact,
                            least_friction=self.least_friction, collision=self.collision,
                            clearance=self.clearance, approaches=approaches or 1,
                            depths=depths or 1, tilt=float(self.tilt), epsilon=self.epsilon,
                            support=support, robust=self.robust, metrics=self.metrics,
                            task=self.task)
        s = found.summary
        extra: dict[str, Any] = {}
        if found.robust is not None:
            extra["robust_probability_mean"] = found.robust["probability_mean"]
        if found.task is not None:
            extra["task_counts"] = {v: found.task[v] for v in TASK_VERDICTS}
        return {"contact": self.contact, "mu": self.mu, "width": s["width"],
                "pad_radius": self.pad_radius, "seed": seed, "grasps": s["candidates"],
                **{v: s[v] for v in VERDICT_WORDS},
                "epsilon_median": s["epsilon_median"],
                "least_friction_median": s["least_friction_median"],
                "collides": s["collides"], "closure_clear": s["closure_clear"],
                "attempts": int(s["attempts"]), "rejected": int(sum(s["rejected"].values())),
                "rejected_reasons": dict(s["rejected"]), **extra, "_labels": found.labels}

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
        return None if record.get("status") != "done" else labels_problem(folder, record)

    def write_tables(self, out: Path, records: Iterable[dict[str, Any]]) -> Path:
        """Write ``out/grasps.parquet`` from the done records' labels files, then the
        exports (:func:`write_exports`)."""
        import json

        from ..files.outdir import write_atomically

        records = list(records)
        table = write_grasp_table(out, records)
        # files kept from the run before only if drawn with the same options
        options = {"graspnet_score": self.graspnet_score, "plot_top": int(self.plot_top)}
        file = Path(out) / EXPORTS_FILE
        try:
            held = json.loads(file.read_text(encoding="utf-8")) if file.is_file() else {}
        except (OSError, ValueError, UnicodeDecodeError, RecursionError):
            held = {}
        keep = isinstance(held, dict) and held.get("options") == options
        if self.exports:
            write_exports(out, records, self.exports, self.graspnet_score, keep=keep)
        if self.plot or self.html:
            write_pictures(out, records, self, keep=keep)
        if self.exports or self.plot or self.html:
            report = json.loads(file.read_text(encoding="utf-8"))
            write_atomically(file, json.dumps({**report, "options": options}, indent=2) + "\n")
        return table


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
    from ..files.outdir import atomic_file

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


def read_records(out: str | Path) -> list[dict[str, Any]]:
    """The readable records of a dataset folder (``out/objects/*.json``), in file order; a
    file that is not JSON or not a record is passed over."""
    import json

    records = []
    for file in sorted((Path(out) / "objects").glob("*.json")):
        try:
            record = json.loads(file.read_text(encoding="utf-8"))
        except (OSError, ValueError, UnicodeDecodeError, RecursionError):
            continue
        if isinstance(record, dict):
            records.append(record)
    return records


def labels_problem(folder: Path, record: dict[str, Any]) -> str | None:
    """Why a done record's labels file in ``folder`` cannot stand for it (missing, or
    changed since the record was written), or None."""
    name, digest = record.get("labels_file"), record.get("labels_sha256")
    if not isinstance(name, str) or not isinstance(digest, str):
        return "fields missing (labels_file, labels_sha256)"
    file = folder / name
    if Path(name).name != name or not file.is_file():
        return f"its labels file {name[:200]!r} is missing"
    if sha256_of(file) != digest:
        return f"its labels file {name[:200]!r} changed since its record was written"
    return None


def export_dataset(out: str | Path, records: Iterable[dict[str, Any]],
                   graspnet: str | Path | None = None, acronym: str | Path | None = None, *,
                   score: str = "friction", mesh_root: str | None = None,
                   keep: bool = False, verify: bool = True
                   ) -> tuple[list[dict[str, Any]], list[tuple[dict[str, Path], str]]]:
    """Each done record's labels as ``graspnet/<stem>.npy`` and ``acronym/<stem>.h5``
    (``<stem>`` the labels file's), as ``forceclosure export DIR`` and ``dataset --export``
    write them (:func:`forceclosure.io.label_files.export_labels_file`).

    A labels file missing, or (with ``verify``: its SHA-256 read again) changed since its
    record was written, is not exported. With ``keep``, an object whose files are all
    at least as new as its labels file is not written again (its entry says ``"kept"``).

    Returns
    -------
    (entries, errors)
        One entry per object exported (or kept); per object that could not be, the files
        it was to be written to (by kind) and the reason in one line.
    """
    import json

    from ..io.label_files import export_labels_file

    out = Path(out)
    job = json.loads((out / "job.json").read_text(encoding="utf-8"))
    for folder in (graspnet, acronym):
        if folder is not None:
            Path(folder).mkdir(parents=True, exist_ok=True)
    done = sorted((r for r in records if r.get("status") == "done"
                   and isinstance(r.get("labels_file"), str)), key=lambda r: r["labels_file"])
    entries: list[dict[str, Any]] = []
    errors: list[tuple[dict[str, Path], str]] = []
    for record in done:
        labels_file = out / "objects" / Path(record["labels_file"]).name
        stem = labels_file.stem
        targets = {kind: Path(folder) / (stem + suffix) for kind, folder, suffix in (
            ("graspnet", graspnet, ".npy"), ("acronym", acronym, ".h5")) if folder is not None}
        try:
            problem = labels_problem(out / "objects", record) if verify else (
                None if labels_file.is_file() else "its labels file is missing")
            if problem is not None:
                raise InputError(f"{record.get('name') or stem}: {problem}; run the dataset "
                                 "again")
            if keep and all(t.is_file() and t.stat().st_mtime_ns
                            >= labels_file.stat().st_mtime_ns for t in targets.values()):
                entries.append({"labels": str(labels_file), "kept": sorted(targets)})
                continue
            entries.append(export_labels_file(
                str(labels_file), *(str(targets[k]) if k in targets else None
                                    for k in ("graspnet", "acronym")),
                score=score, mesh_root=mesh_root, record=record, job=job))
        except (InputError, OSError) as e:
            errors.append((targets, str(e)))
    return entries, errors


def write_exports(out: str | Path, records: Iterable[dict[str, Any]],
                  exports: Iterable[tuple[str, str]], score: str = "friction",
                  keep: bool = True) -> dict[str, Any]:
    """:func:`export_dataset` for ``dataset --export``, one ``(kind, folder)`` at a time (a
    kind that fails for an object leaves the others written); returns, and writes to
    ``out/exports.json``, the files written or kept per kind and the files that could not
    be written (one line each). The run has checked its records' labels files already
    (:meth:`GripperJob.check`), so they are not hashed again here."""
    import json

    from ..files.outdir import write_atomically

    out = Path(out)
    records = list(records)
    report: dict[str, Any] = {"files": {}, "errors": []}
    for kind, folder in exports:
        entries, errors = export_dataset(out, records, **{kind: folder}, score=score,
                                         keep=keep, verify=False)
        report["files"][kind] = report["files"].get(kind, 0) + len(entries)
        report["errors"] += [f"{kind} {targets[kind].name}: {why}" for targets, why in errors]
    write_atomically(out / EXPORTS_FILE, json.dumps(report, indent=2) + "\n")
    return report


def _stale(target: Path, source: Path) -> bool:
    """Whether ``target`` is missing or older than ``source``."""
    return not (target.is_file() and source.is_file()
                and target.stat().st_mtime_ns >= source.stat().st_mtime_ns)


def write_pictures(out: str | Path, records: Iterable[dict[str, Any]], job: GripperJob,
                   keep: bool = True) -> dict[str, Any]:
    """Each done record's ``job.plot_top`` best poses as ``job.plot/<stem>.png`` and
    ``job.html/<stem>.html`` (those ``grasps --plot`` and ``--html`` draw; a file at least as
    new as its labels file is kept, unless ``keep`` is False). The pages share one
    ``job.html/plotly.min.js`` (``grasps --html-shared``'s: each page its figure only).
    Returns the files per kind and the objects that could not be drawn, also added to
    ``out/exports.json``."""
    import json

    from ..files.outdir import write_atomically
    from ..gripper.labels import GraspLabels
    from ..objects.io import load_object
    from ..pictures.plot import upright_axis

    out = Path(out)
    kinds = [(k, Path(f)) for k, f in (("plot", job.plot), ("html", job.html)) if f]
    report: dict[str, Any] = {"files": {k: 0 for k, _ in kinds}, "errors": []}
    for _, folder in kinds:
        folder.mkdir(parents=True, exist_ok=True)
    gripper = job.gripper()
    done = sorted((r for r in records if r.get("status") == "done"
                   and isinstance(r.get("labels_file"), str)), key=lambda r: r["labels_file"])
    if job.html and done:  # the pages kept from a run before load it too
        from ..pictures.page import write_plotly_js

        write_plotly_js(Path(job.html))
    for record in done:
        labels_file = out / "objects" / Path(record["labels_file"]).name
        targets = [(k, folder / (labels_file.stem + (".png" if k == "plot" else ".html")))
                   for k, folder in kinds]
        todo = [(k, t) for k, t in targets if not keep or _stale(t, labels_file)]
        report_done = [k for k, t in targets if (k, t) not in todo]
        for k in report_done:
            report["files"][k] += 1
        if not todo:
            continue
        try:
            source = record.get("path")
            obj = load_object(source, allow_open=job.allow_open,
                              allow_outside_meshes=job.allow_outside_meshes)
            labels = GraspLabels.load(str(labels_file))
            up = upright_axis(source, obj)
            for kind, target in todo:
                if kind == "plot":
                    from ..pictures.grasp_plot import plot_grasps

                    plot_grasps(obj, labels, str(target), top=job.plot_top, gripper=gripper,
                                up=up)
                else:
                    from ..pictures.view import write_grasps_html

                    write_grasps_html(obj, labels, target, top=job.plot_top, gripper=gripper,
                                      up=up, shared_js=True)
                report["files"][kind] += 1
        except (InputError, OSError) as e:
            report["errors"].append(f"pictures of {labels_file.stem}: "
                                    f"{str(e).splitlines()[0]}")
    file = out / EXPORTS_FILE
    try:
        held = json.loads(file.read_text(encoding="utf-8")) if file.is_file() else {}
    except (OSError, ValueError):
        held = {}
    if not isinstance(held, dict) or not isinstance(held.get("files"), dict):
        held = {"files": {}, "errors": []}
    merged = {"files": {**{k: v for k, v in held["files"].items() if k not in ("plot", "html")},
                        **report["files"]},
              "errors": [e for e in held.get("errors", []) if not e.startswith("pictures of ")]
              + report["errors"]}
    write_atomically(file, json.dumps(merged, indent=2) + "\n")
    return report
