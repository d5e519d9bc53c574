"""The labelling pipeline of parallel-jaw poses, and its summary, in one call.

:func:`label_poses` runs the stages a user of jaw poses asks for, in one order:
the poses and their labels (:func:`~forceclosure.gripper.labels.grasp_labels`:
Theorem 1's verdict with exact cones, the least friction, the Ferrari–Canny ε),
then optionally the probability of force closure under noise
(:func:`~forceclosure.gripper.robust.robust_labels`), the grasp-matrix metrics
(:func:`~forceclosure.gripper.labels.label_metrics`) and the test against a
task's weight (:func:`~forceclosure.gripper.labels.label_task`). It returns
the labels with every array asked for, and the summary of each stage (counts,
medians, timings) computed here once: the ``grasps`` command prints it and the
dataset records it.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Mapping
from contextlib import AbstractContextManager, contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..analysis.task import TASK_VERDICTS
from ..errors import InputError
from ..verdicts import VERDICT_WORDS, VerdictCode, closed_median
from .hand_poses import APPROACHES, DEPTHS
from .jaw import ParallelJaw
from .labels import METRIC_ARRAYS, GraspLabels, grasp_labels
from .settings import ROBUST_DEFAULTS, TASK_DEFAULTS

__all__ = ["LabelledPoses", "Stage", "label_poses"]


#: A stage's progress: called with the stage's name (``"labelling"``, ``"robustness"``,
#: ``"metrics"``, ``"task wrench"``), its total and its unit (``" grasps"``, ``" samples"``);
#: gives a context whose value is called with each step's count.
Stage = Callable[[str, int, str], AbstractContextManager[Callable[[int], object]]]


@contextmanager
def _silent(name: str, total: int, unit: str) -> Iterator[Callable[[int], object]]:
    yield lambda n: None


def _median(values: NDArray[np.float64]) -> float | None:
    """The median, or None for no values or any that is not finite."""
    return float(np.median(values)) if len(values) and np.all(np.isfinite(values)) else None


def _rate(count: int, seconds: float) -> int | None:
    return round(count / seconds) if seconds > 0 else None


@dataclass(frozen=True)
class LabelledPoses:
    """What :func:`label_poses` returns: the labels and the summary of each stage.

    Attributes
    ----------
    labels : GraspLabels
        The poses and their labels, with the robustness, metric and task arrays asked for.
    summary : dict
        ``candidates``, ``requested``, ``attempts``, ``rejected`` (lines that made no pose,
        by reason), ``contact``, ``mu``, ``width``, ``gripper``, the count of each verdict,
        ``least_friction_median`` (None when not computed or when the median pose closes
        with no friction), ``epsilon_median`` (of the closed poses), the collision counts
        (``collides``, ``collides_<verdict>``, ``closure_clear``; None without the check),
        ``approaches``, ``depths``, ``hand_poses_tried``, ``support_plane``, ``seconds``
        and ``grasps_per_second`` of the labelling.
    robust, metrics, task : dict or None
        The summary of each optional stage that ran: its settings, its medians (counts for
        the task), its ``seconds`` and rate.
    """

    labels: GraspLabels
    summary: dict[str, Any]
    robust: dict[str, Any] | None = None
    metrics: dict[str, Any] | None = None
    task: dict[str, Any] | None = None


def label_poses(obj: Any, gripper: ParallelJaw, mu: float, count: int, seed: int = 0,
                contact: str = "soft", *, least_friction: bool = True, epsilon: bool = True,
                collision: bool = True, clearance: float | None = None,
                approaches: int = APPROACHES, depths: int = DEPTHS, tilt: float = 0.0,
                support: Any = None, robust: Mapping[str, Any] | None = None,
                metrics: bool = False, task: Mapping[str, Any] | None = None,
                stage: Stage | None = None) -> LabelledPoses:
    """Sample and label jaw poses, with the optional stages, and summarise every stage.

    The poses and their labels are those of
    :func:`~forceclosure.gripper.labels.grasp_labels` (verdicts by Theorem 1 with exact
    circular cones; the least friction; the Ferrari–Canny ε), which takes the arguments
    up to ``support``. Then, as asked:

    * ``robust`` (settings as :data:`~forceclosure.gripper.settings.ROBUST_DEFAULTS`,
      each key optional): the probability of force closure and the expected ε under noise
      (:func:`~forceclosure.gripper.robust.robust_labels`, seeded by ``seed``);
    * ``metrics``: the grasp matrix's singular values, isotropy and wrench-hull volume;
    * ``task`` (``mass``, and optionally ``gravity``, ``f_max`` and ``edges``, defaults
      :data:`~forceclosure.gripper.settings.TASK_DEFAULTS`):
      whether the jaws, each pressing at most ``f_max``, resist the object's weight at
      its mesh's centre of mass (uniform density; the mesh must be closed).

    Parameters
    ----------
    obj : Polyhedron, trimesh.Trimesh or str
        The object (a bundled name works).
    gripper : ParallelJaw
        The hand (:func:`~forceclosure.gripper.grippers.make_gripper`).
    mu : float
        The friction coefficient.
    count : int
        The poses to sample.
    seed : int
        The seed of the sampling and of the noise.
    contact : {"soft", "hard"}
        The pads' contact model.
    least_friction, epsilon, collision, clearance, approaches, depths, tilt, support
        As :func:`~forceclosure.gripper.labels.grasp_labels`.
    robust : mapping, optional
        Robustness settings; None skips the stage.
    metrics : bool
        Whether to compute the grasp-matrix metrics.
    task : mapping, optional
        The task's ``mass``, ``gravity`` vector and each jaw's largest normal force
        ``f_max``; None skips the stage.
    stage : callable, optional
        Progress of each stage (:data:`Stage`); None reports nothing.

    Returns
    -------
    LabelledPoses

    References
    ----------
    V.-D. Nguyen, "Constructing Force-Closure Grasps", IJRR 7(3), 1988: Theorem 1 (the
    verdicts), §2.1 (soft and hard contacts).

    Examples
    --------
    >>> found = label_poses("cube", ParallelJaw(3.0), mu=0.5, count=20, seed=0,
    ...                     metrics=True, task={"mass": 0.1, "gravity": [0, 0, -9.81], "f_max": 70})
    >>> s, t = found.summary, found.task
    >>> s["candidates"], s["closure"] + s["marginal"] + s["none"]
    (20, 20)
    >>> t["resists"] + t["undecided"] + t["fails"]
    20
    >>> found.metrics["isotropy_median"] <= 1 + 1e-9
    True
    """
    progress = stage or _silent
    if task is not None:
        if getattr(obj, "watertight", True) is False:
            raise InputError(f"{getattr(obj, 'name', 'the object')}: the task's weight needs a "
                             "closed mesh for its centre of mass; this one is open")
        task = {**TASK_DEFAULTS, **task}
        task = {"mass": task["mass"], "gravity": [float(g) for g in task["gravity"]],
                "f_max": task["f_max"], "edges": task["edges"]}
    start = time.perf_counter()
    with progress("labelling", count, " grasps") as step:
        labels = grasp_labels(obj, gripper, mu, count, seed, contact, progress=step,
                              least_friction=least_friction, collision=collision,
                              clearance=clearance, approaches=approaches, epsilon=epsilon,
                              depths=depths, tilt=tilt, support=support)
    seconds = time.perf_counter() - start
    summary = _summary(labels, count, contact, mu, gripper, least_friction, epsilon, support,
                       seconds)
    robust_entry = metrics_entry = task_entry = None
    if robust is not None:
        labels, robust_entry = _robust_stage(obj, labels, gripper, mu, seed, contact,
                                             {**ROBUST_DEFAULTS, **robust}, progress)
    if metrics:
        labels, metrics_entry = _metrics_stage(labels, progress)
    if task is not None:
        labels, task_entry = _task_stage(obj, labels, task, progress)
    return LabelledPoses(labels, summary, robust_entry, metrics_entry, task_entry)


def _summary(labels: GraspLabels, count: int, contact: str, mu: float, gripper: ParallelJaw,
             least_friction: bool, epsilon: bool, support: Any, seconds: float
             ) -> dict[str, Any]:
    """The labelling stage's summary (:attr:`LabelledPoses.summary`)."""
    meta = labels.meta
    mu_star = (float(np.median(labels.least_friction)) if len(labels) and least_friction
               else None)
    return {"candidates": len(labels), "requested": count, "attempts": meta["attempts"],
            "rejected": meta["rejected"], "contact": contact, "mu": mu,
            "width": gripper.width_max, "gripper": gripper.name, **labels.counts(),
            "least_friction_median": mu_star if mu_star is not None and np.isfinite(mu_star)
            else None,
            "epsilon_median": closed_median(labels.epsilon, labels.code) if epsilon else None,
            **_collision_counts(labels),
            "approaches": meta["approaches"], "depths": meta["depths"],
            "hand_poses_tried": meta["tried"],
            "support_plane": None if support is None else support.to_dict(),
            "seconds": round(seconds, 3), "grasps_per_second": _rate(len(labels), seconds)}


def _collision_counts(labels: GraspLabels) -> dict[str, int | None]:
    """Colliding poses, by verdict, and the closed clear ones (None without the check)."""
    keys = ("collides", "collides_closure", "collides_marginal", "collides_none",
            "closure_clear")
    if labels.collides is None:
        return dict.fromkeys(keys)
    hit = labels.collides
    return {"collides": int(hit.sum()),
            **{f"collides_{v}": int(np.sum(hit & (labels.code == c)))
               for c, v in enumerate(VERDICT_WORDS)},
            "closure_clear": int(np.sum(~hit & (labels.code == VerdictCode.CLOSURE)))}


def _robust_stage(obj: Any, labels: GraspLabels, gripper: ParallelJaw, mu: float, seed: int,
                  contact: str, settings: dict[str, Any], progress: Stage
                  ) -> tuple[GraspLabels, dict[str, Any]]:
    from .robust import robust_labels

    if settings["pose_sigma"] is None:
        settings["pose_sigma"] = 0.01 * gripper.width_max
    samples = int(settings["samples"])
    total = len(labels) * samples
    start = time.perf_counter()
    with progress("robustness", total, " samples") as step:
        r = robust_labels(obj, labels, gripper, mu, samples=samples, seed=seed,
                          pose_sigma=settings["pose_sigma"], angle_sigma=settings["angle_sigma"],
                          mu_sigma=settings["mu_sigma"], normal_sigma=settings["normal_sigma"],
                          contact=contact, confidence=settings["confidence"],
                          epsilon=bool(settings["epsilon"]), progress=step)
    seconds = time.perf_counter() - start
    entry = {k: v for k, v in settings.items() if k != "epsilon"}
    entry.update({"probability_mean": float(np.mean(r.probability)) if len(r) else None,
                  "probability_median": _median(r.probability),
                  "epsilon_median": _median(r.epsilon),
                  "missed_fraction": float(r.missed.sum() / total) if total else None,
                  "seconds": round(seconds, 3), "samples_per_second": _rate(total, seconds)})
    return labels.with_robustness(r), entry


def _metrics_stage(labels: GraspLabels, progress: Stage) -> tuple[GraspLabels, dict[str, Any]]:
    from .labels import label_metrics

    start = time.perf_counter()
    with progress("metrics", len(labels), " grasps") as step:
        labels = labels.with_metrics(label_metrics(labels, progress=step))
    seconds = time.perf_counter() - start
    entry: dict[str, Any] = {f"{name}_median": float(np.median(getattr(labels, name)))
                             if len(labels) else None for name in METRIC_ARRAYS}
    entry["seconds"] = round(seconds, 3)
    return labels, entry


def _task_stage(obj: Any, labels: GraspLabels, settings: dict[str, Any], progress: Stage
                ) -> tuple[GraspLabels, dict[str, Any]]:
    from ..analysis.task import gravity_wrench
    from .jaw import surface_mesh
    from .labels import label_task

    com = [float(x) for x in surface_mesh(obj)[1].center_mass]
    settings = {**settings, "center_of_mass": com}
    wrench = gravity_wrench(settings["mass"], com, settings["gravity"])
    start = time.perf_counter()
    with progress("task wrench", len(labels), " grasps") as step:
        code, spare, upper = label_task(labels, wrench, settings["f_max"], settings["edges"],
                                        progress=step)
    seconds = time.perf_counter() - start
    finite = spare[np.isfinite(spare)]
    entry = {**settings, **{v: int(np.sum(code == c)) for c, v in enumerate(TASK_VERDICTS)},
             "spare_median": float(np.median(finite)) if len(finite) == len(spare)
             and len(spare) else None,
             "seconds": round(seconds, 3), "grasps_per_second": _rate(len(labels), seconds)}
    return labels.with_task(code, spare, upper, settings), entry
