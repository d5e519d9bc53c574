"""Certified labels for sampled parallel-jaw grasps.

:func:`label_grasps` labels contact pairs with the batch kernels of
:mod:`forceclosure.analysis.batch`: the verdict with exact circular cones
(Theorem 1), the least friction μ* that closes each pair (one compiled
pass), and the Ferrari–Canny ε (L1, 8-edge inscribed pyramids, torques
about the pair's midpoint per its half-width). :func:`grasp_labels`
finds jaw poses the hand can take and the contacts its pads make
(:mod:`forceclosure.gripper.hand_poses`) and labels them; the result saves as
``.npz``, atomically, and reads back with :meth:`GraspLabels.load`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..verdicts import VERDICT_WORDS, VerdictCode, verdict_counts, verdict_words
from .hand_poses import APPROACHES, DEPTHS
from .jaw import ParallelJaw, check_jaw_contact

__all__ = ["GraspLabels", "grasp_labels", "label_grasps", "label_metrics", "label_task"]


#: The arrays of a saved label file, in order (``GraspLabels.save``).
#: ``collides`` is written only when the collision check ran (``meta["collision"]`` not None).
ARRAYS = ("center", "closing_axis", "approach_axis", "width", "points", "normals", "code",
          "least_friction", "epsilon", "collides")

#: The optional arrays of the pose (:func:`grasp_labels` writes them): how far each pose's
#: fingertips reach past its jaw centre, and each contact's torsional coefficient.
POSE_ARRAYS = ("depth", "torsion")

#: The optional arrays of robustness (:meth:`GraspLabels.with_robustness`), saved when present.
ROBUST_ARRAYS = ("robust_probability", "robust_probability_low", "robust_probability_high",
                 "robust_epsilon", "robust_epsilon_low", "robust_epsilon_high", "robust_missed")

#: The optional arrays of grasp-matrix metrics (:meth:`GraspLabels.with_metrics`), saved when
#: present; named as the fields of :class:`~forceclosure.analysis.metrics.GraspMetrics`.
METRIC_ARRAYS = ("sigma_min", "sigma_max", "isotropy", "volume")

#: The optional arrays of the task-wrench test (:meth:`GraspLabels.with_task`), saved when
#: present.
TASK_ARRAYS = ("task_verdict", "task_spare", "task_spare_upper")


@dataclass(frozen=True, eq=False)
class GraspLabels:
    """``N`` jaw poses, their contact pairs and labels.

    Attributes
    ----------
    center, closing_axis, approach_axis : (N, 3) arrays
    width : (N,) array
    points, normals : (N, 2, 3) arrays
    code : (N,) int8 array
        0 ``none``, 1 ``marginal``, 2 ``closure`` (exact cones, at ``mu``).
    least_friction : (N,) array
        μ*: the least friction, equal at both contacts, closing the pair
        (``inf``: none does; NaN: not computed).
    epsilon : (N,) array
        Ferrari–Canny ε (L1), 0 where not closed (NaN: not computed).
    meta : dict
        ``object``, ``mu``, ``contact``, ``torsion``, ``width_max``,
        ``pad_radius``, ``seed``, ``attempts``, ``rejected``, ``collision``
        (the check's ``clearance`` and the hand's boxes, or None: not checked),
        ``approaches`` (approach axes tried per pair; None: not checked);
        with robustness also ``robust`` (samples, seed, confidence, noise); with the
        task test also ``task`` (mass, gravity, center_of_mass, f_max, edges).
    collides : (N,) bool array or None
        Whether the hand, opened at the pose, meets the object
        (:func:`~forceclosure.gripper.collision.collides`); None when not checked. A
        colliding grasp keeps its verdict: the labels certify its contacts,
        and ``collides`` says the gripper cannot reach them as posed.
    robust_probability, robust_probability_low, robust_probability_high : (N,) arrays or None
        Probability of force closure under noise and its Wilson interval
        (:func:`forceclosure.gripper.robust.robust_labels`); None when not computed.
    robust_epsilon, robust_epsilon_low, robust_epsilon_high : (N,) arrays or None
        Mean epsilon under noise and its Student-t interval (NaN: not computed).
    robust_missed : (N,) int array or None
        Noise samples whose jaws made no contact pair (counted as not closed).
    sigma_min, sigma_max, isotropy, volume : (N,) arrays or None
        Grasp-matrix metrics of the contact pairs (:func:`label_metrics`): smallest and
        largest singular values, their ratio, and the volume of the wrench hull; None when
        not computed.
    task_verdict : (N,) int8 array or None
        The task-wrench test (:func:`label_task`): 0 ``fails`` (proved, circumscribed
        pyramids), 1 ``undecided``, 2 ``resists`` (proved, inscribed pyramids).
    task_spare, task_spare_upper : (N,) arrays or None
        The largest multiple of the task wrench resisted: lower bound (inscribed pyramids)
        and upper bound (circumscribed).
    depth : (N,) array or None
        How far each pose's fingertips reach past its jaw centre along the approach axis
        (None: the gripper's ``depth`` for every pose); the hand's base frame is
        ``meta["tip_offset"] - depth`` behind the centre.
    torsion : (N, 2) array or None
        Each soft pad's torsional coefficient (its twisting torque is at most this
        times its normal force), from the region it presses (``meta["torsion"]`` is
        then ``"pressed"``); None: one coefficient for all in ``meta["torsion"]``
        (None there: the paper's unlimited torque).
    """

    center: NDArray[np.float64]
    closing_axis: NDArray[np.float64]
    approach_axis: NDArray[np.float64]
    width: NDArray[np.float64]
    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    code: NDArray[np.int8]
    least_friction: NDArray[np.float64]
    epsilon: NDArray[np.float64]
    meta: dict[str, Any] = field(default_factory=dict)
    collides: NDArray[np.bool_] | None = None
    robust_probability: NDArray[np.float64] | None = None
    robust_probability_low: NDArray[np.float64] | None = None
    robust_probability_high: NDArray[np.float64] | None = None
    robust_epsilon: NDArray[np.float64] | None = None
    robust_epsilon_low: NDArray[np.float64] | None = None
    robust_epsilon_high: NDArray[np.float64] | None = None
    robust_missed: NDArray[np.int64] | None = None
    sigma_min: NDArray[np.float64] | None = None
    sigma_max: NDArray[np.float64] | None = None
    isotropy: NDArray[np.float64] | None = None
    volume: NDArray[np.float64] | None = None
    task_verdict: NDArray[np.int8] | None = None
    task_spare: NDArray[np.float64] | None = None
    task_spare_upper: NDArray[np.float64] | None = None
    depth: NDArray[np.float64] | None = None
    torsion: NDArray[np.float64] | None = None

    def __len__(self) -> int:
        return len(self.code)

    @property
    def verdict(self) -> NDArray[np.str_]:
        """``"closure"``, ``"marginal"`` or ``"none"`` per grasp."""
        return verdict_words(self.code)

    def counts(self) -> dict[str, int]:
        """How many grasps have each verdict."""
        counts = verdict_counts(self.code)
        return {word: counts[word] for word in VERDICT_WORDS}  # in the codes' order

    def with_robustness(self, robustness: Any) -> GraspLabels:
        """These labels with the arrays of a :class:`~forceclosure.gripper.robust.Robustness` of the
        same grasps, and its settings in ``meta["robust"]``."""
        r = robustness
        if len(r) != len(self):
            raise InputError(f"robustness of {len(r)} grasps for {len(self)} labels")
        meta = dict(self.meta)
        meta["robust"] = {"samples": r.samples, "seed": r.seed, "confidence": r.confidence,
                          **r.noise.to_dict()}
        return replace(self, meta=meta, robust_probability=r.probability,
                       robust_probability_low=r.probability_low,
                       robust_probability_high=r.probability_high, robust_epsilon=r.epsilon,
                       robust_epsilon_low=r.epsilon_low, robust_epsilon_high=r.epsilon_high,
                       robust_missed=r.missed)

    def with_metrics(self, metrics: Any) -> GraspLabels:
        """These labels with the arrays of a :class:`~forceclosure.analysis.metrics.GraspMetrics` of
        the same grasps (:func:`label_metrics`)."""
        if len(metrics) != len(self):
            raise InputError(f"metrics of {len(metrics)} grasps for {len(self)} labels")
        arrays: dict[str, Any] = {n: np.asarray(getattr(metrics, n), dtype=float)
                                  for n in METRIC_ARRAYS}
        return replace(self, **arrays)

    def with_task(self, verdict: ArrayLike, spare: ArrayLike, spare_upper: ArrayLike,
                  settings: dict[str, Any]) -> GraspLabels:
        """These labels with the task-wrench arrays of the same grasps (:func:`label_task`)
        and the test's ``settings`` in ``meta["task"]``."""
        arrays = [np.asarray(verdict, dtype=np.int8), np.asarray(spare, dtype=float),
                  np.asarray(spare_upper, dtype=float)]
        if any(a.shape != (len(self),) for a in arrays):
            raise InputError(f"task arrays of shapes {[a.shape for a in arrays]} for "
                             f"{len(self)} labels")
        meta = dict(self.meta)
        meta["task"] = dict(settings)
        return replace(self, meta=meta, **dict(zip(TASK_ARRAYS, arrays, strict=True)))

    def _arrays(self) -> tuple[str, ...]:
        """The names of the arrays present: :data:`ARRAYS`, then any of :data:`ROBUST_ARRAYS`,
        :data:`METRIC_ARRAYS`, :data:`TASK_ARRAYS` and :data:`POSE_ARRAYS`."""
        return ARRAYS + tuple(n for n in ROBUST_ARRAYS + METRIC_ARRAYS + TASK_ARRAYS
                              + POSE_ARRAYS if getattr(self, n) is not None)

    def to_dict(self) -> dict[str, Any]:
        """Every array as nested lists (``inf`` μ*, NaN ε and ``inf`` spares as None) and the
        metadata; JSON-ready."""
        out: dict[str, Any] = {"meta": dict(self.meta), "verdict": self.verdict.tolist()}
        for name in self._arrays():
            a = getattr(self, name)
            if a is None:
                out[name] = None
                continue
            out[name] = ([None if not np.isfinite(x) else float(x) for x in a]  # inf, NaN
                         if name in ("least_friction", "epsilon", "task_spare",
                                     "task_spare_upper") or name.startswith("robust_epsilon")
                         else a.tolist())
        return out

    def save(self, path: str) -> None:
        """Write the arrays (:data:`ARRAYS`, and those of :data:`ROBUST_ARRAYS`,
        :data:`METRIC_ARRAYS` and :data:`TASK_ARRAYS` present) and
        ``meta`` (as JSON text) to an ``.npz``, atomically
        (:func:`forceclosure.files.atomic.atomic_write`)."""
        import json

        from ..files.atomic import atomic_write

        arrays = {name: getattr(self, name) for name in self._arrays()
                  if getattr(self, name) is not None}
        arrays["meta"] = np.array(json.dumps(self.meta))
        with atomic_write(path) as f:
            np.savez_compressed(f, **arrays)

    @classmethod
    def load(cls, source: Any) -> GraspLabels:
        """Read labels written by :meth:`save`: a path to the ``.npz``, or what ``np.load``
        returned for one (or any mapping of its arrays).

        Every array of :data:`ARRAYS` but ``collides`` is required, with ``meta`` (JSON text
        of an object); ``collides`` and the arrays of :data:`ROBUST_ARRAYS`,
        :data:`METRIC_ARRAYS`, :data:`TASK_ARRAYS` (and any other per-grasp array that is a
        field of the class, such as a per-pose ``depth``) are read when present; arrays
        that are not fields are left out. A file that is not a label file (not an
        ``.npz``, an array missing, of the wrong shape, verdict codes other than 0, 1, 2, a
        ``meta`` that is not a JSON object) is refused in one line naming it.

        Examples
        --------
        >>> import os, tempfile
        >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=4, collision=False)
        >>> path = os.path.join(tempfile.mkdtemp(), "l.npz")
        >>> labels.save(path)
        >>> back = GraspLabels.load(path)
        >>> bool(np.array_equal(back.points, labels.points)), back.meta == labels.meta
        (True, True)
        >>> GraspLabels.load(np.load(path)).collides is None
        True
        """
        import os
        from collections.abc import Mapping

        from ..errors import first_line

        if isinstance(source, str | os.PathLike):
            where = os.fspath(source)
            if not os.path.exists(where):
                raise InputError(f"{where}: no such label file")
            import zipfile

            if os.path.isfile(where) and not zipfile.is_zipfile(where):
                raise InputError(f"{where}: not a label file: not an .npz archive (the .npz "
                                 "that GraspLabels.save writes)")
            try:
                data = np.load(where, allow_pickle=False)
            except Exception as e:  # a folder, not a zip, truncated: numpy raises many types
                raise InputError(f"{where}: not a label file (.npz): {first_line(e)}") from None
            if not isinstance(data, np.lib.npyio.NpzFile):
                raise InputError(f"{where}: not a label file: one array (.npy), not the .npz "
                                 "of labels that GraspLabels.save writes")
            with data:
                return cls._from_arrays(data, where)
        if isinstance(source, Mapping | np.lib.npyio.NpzFile):
            return cls._from_arrays(source, "labels")
        raise InputError(f"labels: expected a label file's path or its np.load arrays, got "
                         f"a {type(source).__name__}")

    @classmethod
    def _from_arrays(cls, data: Any, where: str) -> GraspLabels:
        """:meth:`load` from a mapping of arrays; ``where`` names the source in errors."""
        import json
        from dataclasses import fields

        from ..errors import first_line

        names = set(data.keys()) if hasattr(data, "keys") else set(data)
        required = ["center", "closing_axis", "approach_axis", "width", "points", "normals",
                    "code", "least_friction", "epsilon", "meta"]
        missing = [n for n in required if n not in names]
        if missing:
            raise InputError(f"{where}: not a label file: no {', '.join(map(repr, missing))} "
                             f"array{'s' if len(missing) > 1 else ''} (GraspLabels.save "
                             f"writes {', '.join(required)})")

        def read(name: str) -> NDArray[Any]:
            try:
                return np.asarray(data[name])
            except Exception as e:  # a damaged member, or one stored as pickled objects
                raise InputError(f"{where}: cannot read its array {name!r}: "
                                 f"{first_line(e)}") from None

        raw = read("meta")
        try:
            meta = json.loads(str(raw[()])) if raw.shape == () else None
        except ValueError:
            meta = None
        if not isinstance(meta, dict):
            raise InputError(f"{where}: not a label file: its 'meta' is not the JSON text of "
                             "an object")
        n = len(read("code").reshape(-1))
        shapes = {"center": (n, 3), "closing_axis": (n, 3), "approach_axis": (n, 3),
                  "points": (n, 2, 3), "normals": (n, 2, 3), "torsion": (n, 2)}
        kinds = {"code": np.int8, "collides": np.bool_, "task_verdict": np.int8,
                 "robust_missed": np.int64}
        values: dict[str, Any] = {"meta": meta}
        for f in fields(cls):
            if f.name == "meta" or f.name not in names:
                continue
            a = read(f.name)
            shape = shapes.get(f.name, (n,))
            if a.shape != shape:
                raise InputError(f"{where}: its array {f.name!r} has shape {a.shape}; "
                                 f"{shape} expected for {n} grasps")
            kind = kinds.get(f.name, np.float64)
            if kind is np.bool_ and a.dtype != np.bool_:
                raise InputError(f"{where}: its array {f.name!r} is {a.dtype}, not bool")
            if kind in (np.int8, np.int64) and not np.issubdtype(a.dtype, np.integer):
                raise InputError(f"{where}: its array {f.name!r} is {a.dtype}, not integer")
            if kind is np.float64 and not (np.issubdtype(a.dtype, np.floating)
                                           or np.issubdtype(a.dtype, np.integer)):
                raise InputError(f"{where}: its array {f.name!r} is {a.dtype}, not numbers")
            if f.name in ("code", "task_verdict") and np.any((a < 0) | (a > 2)):
                raise InputError(f"{where}: its {f.name!r} codes must be 0, 1 or 2")
            values[f.name] = a.astype(kind)
        return cls(**values)


#: Grasps labelled at a time (the progress callback is called after each chunk).
CHUNK = 2048


def label_grasps(points: ArrayLike, normals: ArrayLike, mu: float, contact: str = "soft",
                 torsion: float | NDArray[np.float64] | None = None,
                 progress: Callable[[int], object] | None = None, least_friction: bool = True,
                 epsilon: bool = True
                 ) -> tuple[NDArray[np.int8], NDArray[np.float64], NDArray[np.float64]]:
    """Verdict codes, least friction and epsilon of ``N`` contact pairs (``(N, 2, 3)``).

    ``contact`` is ``"soft"`` (pads: a torque about the normal, uncoupled,
    or bounded by ``torsion`` times the normal force: one number, or ``(N, 2)``
    one a contact) or ``"hard"`` (point
    contacts; two of them never close a spatial grasp: nothing resists
    rotation about the line through them). μ* is computed with ``torsion``
    held at the value given. ``progress`` is called with the number of
    grasps just labelled, after every :data:`CHUNK` of them. Soft pads with
    the paper's torque (``torsion`` None) and hard contacts have their verdict and μ*
    in closed form, all pairs in one compiled pass, under a µs a pair
    (:func:`forceclosure.analysis.two_finger.pair_labels`); with a coupled
    ``torsion``, μ* is a bisection of verdicts, milliseconds a pair;
    ``least_friction=False`` skips it (NaN). ε (about
    130 µs a closed soft pair) is most of the rest: ``epsilon=False`` skips
    it (NaN for every grasp).

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, Corollary 3
    .. [2] C. Ferrari and J. Canny, "Planning optimal grasps", *Proc. IEEE ICRA*, 1992,
       pp. 2290-2295

    Examples
    --------
    A pinch across the 2-unit cube, the jaws' line tilted by 0.2 / 2: μ* is
    tan of the tilt (Corollary 3; the normals are antiparallel).

    >>> P = np.array([[[-1, 0, 0], [1, 0.2, 0]]])
    >>> N = np.array([[[-1.0, 0, 0], [1, 0, 0]]])
    >>> code, mu_star, eps = label_grasps(P, N, mu=0.3)
    >>> code.tolist(), round(float(mu_star[0]), 5), bool(eps[0] > 0)
    ([2], 0.1, True)
    >>> label_grasps(P, N, mu=0.3, least_friction=False, epsilon=False)[2].tolist()
    [nan]
    """
    from ..analysis.batch import epsilon_batch, least_friction_batch
    from ..analysis.two_finger import pair_codes, pair_labels

    check_jaw_contact(contact)
    points = np.asarray(points, dtype=float)
    normals = np.asarray(normals, dtype=float)
    n = len(points)
    eps = np.zeros(n) if epsilon else np.full(n, np.nan)
    closed_form = torsion is None  # verdict and μ* of every pair in one compiled pass
    if closed_form:
        code, mu_star = pair_labels(points, normals, mu, contact)
        if not least_friction:
            mu_star.fill(np.nan)
        if not epsilon and progress is None:
            return code, mu_star, eps  # nothing left to do by chunks
    else:
        code, mu_star = np.zeros(n, np.int8), np.full(n, np.nan)
    each = (np.broadcast_to(np.asarray(torsion, dtype=float), (n, 2))  # one a contact
            if torsion is not None and np.ndim(torsion) > 0 else None)
    for lo in range(0, n, CHUNK):
        part = slice(lo, min(n, lo + CHUNK))
        P, N = points[part], normals[part]
        T = torsion if each is None else each[part]
        if not closed_form:  # coupled torsion: Theorem 1 and a bisection
            code[part] = pair_codes(P, N, mu, contact, T)
            if least_friction:
                mu_star[part] = least_friction_batch(P, N, model=contact, torsion=T)
        closed = (np.flatnonzero(code[part] == VerdictCode.CLOSURE) if epsilon
                  else np.zeros(0, np.int64))
        if len(closed):
            eps[lo + closed] = epsilon_batch(P[closed], N[closed], mu=mu, model=contact,
                                             torsion=T if each is None else each[part][closed])
        if progress is not None:
            progress(part.stop - part.start)
    return code, mu_star, eps


def grasp_labels(obj: Any, gripper: ParallelJaw, mu: float, count: int, seed: int = 0,
                 contact: str = "soft", progress: Callable[[int], object] | None = None,
                 least_friction: bool = True, collision: bool = True,
                 clearance: float | None = None, approaches: int = APPROACHES,
                 epsilon: bool = True, depths: int = DEPTHS, tilt: float = 0.0,
                 support: Any = None) -> GraspLabels:
    """Sample ``count`` jaw poses on ``obj`` that ``gripper`` can take, and label them.

    Closing lines are drawn through surface points along their inward normals
    (``tilt`` > 0: inside that share of the friction cone); along each the
    hand's approach (``approaches`` axes about the closing axis) and depth
    (``depths`` fingertip depths over the pad) are searched for a pose at
    which the opened hand, its fingers a ``clearance`` off the contacts
    (default :data:`~forceclosure.gripper.collision.CLEARANCE` ×
    ``width_max``), clears the object; the contacts are where the flat pads
    first touch it (:func:`~forceclosure.gripper.hand_poses.search_poses`).
    ``collides`` marks the lines where no pose tried clears (their first pose
    with contacts is kept); ``collision=False`` checks nothing (``collides``
    None) and keeps each line's first pose. The labels (verdict, μ*, ε) are of
    each kept pose's contacts; ``least_friction=False`` and ``epsilon=False``
    skip μ* and ε (NaN), as in :func:`label_grasps`. Soft pads resist
    twisting as ``gripper.torsion`` says (bounded by the pad unless its
    ``pad_radius`` is 0).

    ``meta`` records the gripper (``gripper``, ``tip_offset``, every size under
    ``hand``; with the check, the clearance and sizes under ``collision``),
    ``approaches`` and ``depths`` tried (None without the check), ``tried`` (hand
    poses checked), ``tilt`` and ``warnings`` (an opening far from the object's
    size).

    ``support`` (a :class:`~forceclosure.gripper.support.SupportPlane`): a table the hand
    must not cross (:func:`~forceclosure.gripper.hand_poses.search_poses`), recorded in
    ``meta["support_plane"]``.

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, Corollary 3 (two
       opposing fingers)
    .. [2] C. Ferrari and J. Canny, "Planning optimal grasps", *Proc. IEEE ICRA*, 1992,
       pp. 2290-2295
    .. [3] J. Mahler et al., "Dex-Net 2.0: Deep learning to plan robust grasps with
       synthetic point clouds and analytic grasp metrics", *Robotics: Science and
       Systems*, 2017

    Examples
    --------
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=20, seed=0)
    >>> len(labels), sum(labels.counts().values())
    (20, 20)
    >>> bool(np.all(labels.least_friction[labels.code == VerdictCode.CLOSURE] < 0.3))
    True
    >>> labels.collides.shape, grasp_labels("cube", ParallelJaw(3.0), 0.3, 5,
    ...                                     collision=False).collides
    ((20,), None)
    """
    from .hand_poses import search_poses, units_warning
    from .jaw import surface_mesh

    if not isinstance(gripper, ParallelJaw):
        raise InputError(f"gripper must be a ParallelJaw, got {type(gripper).__name__}")
    check_jaw_contact(contact)
    try:
        mu = float(mu)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"mu must be a number, got {mu!r}") from None
    if not np.isfinite(mu) or mu <= 0:
        raise InputError(f"mu must be finite and positive, got {mu}")
    poly, _ = surface_mesh(obj)
    warning = units_warning(gripper, poly.size)
    poses = search_poses(poly, gripper, mu, count, seed, approaches if collision else 1,
                         depths if collision else 1, clearance, collision, tilt, support)
    pressed = contact == "soft" and gripper.pad_radius is None
    each = mu * poses.lever if pressed else None  # one a contact, from the pressed regions
    torsion = each if pressed else gripper.torsion(mu) if contact == "soft" else None
    code, mu_star, eps = label_grasps(poses.points, poses.normals, mu, contact, torsion,
                                      progress, least_friction, epsilon)
    checked = None
    if collision:
        from .collision import CLEARANCE

        c = CLEARANCE * gripper.width_max if clearance is None else float(clearance)
        checked = {"clearance": c, **{k: v for k, v in gripper.shape().items()
                                       if k not in ("width_max", "pad_radius", "name")}}
    name = obj if isinstance(obj, str) else getattr(obj, "name", type(obj).__name__)
    meta = {"object": str(name), "mu": float(mu), "contact": contact,
            "torsion": "pressed" if pressed else torsion,
            "width_max": gripper.width_max, "pad_radius": gripper.pad_radius, "seed": seed,
            "attempts": poses.attempts, "rejected": poses.rejected, "collision": checked,
            "approaches": int(approaches) if collision else None,
            "depths": int(depths) if collision else None, "tried": poses.tried,
            "gripper": gripper.name, "tip_offset": gripper.tip_offset, "tilt": tilt,
            "hand": gripper.shape(),
            "contacts": "pads", "warnings": [warning] if warning else []}
    if support is not None:
        meta["support_plane"] = support.to_dict()
    return GraspLabels(poses.center, poses.closing_axis, poses.approach_axis, poses.width,
                       poses.points, poses.normals, code, mu_star, eps, meta,
                       collides=poses.collides, depth=poses.depth,
                       torsion=each)


def torsion_of(labels: GraspLabels) -> Any:
    """The labels' torsional coefficients: their per-contact array where the pads' pressed
    regions gave one, else the one value of ``meta["torsion"]`` (None: unlimited)."""
    if labels.torsion is not None:
        return labels.torsion
    value = labels.meta.get("torsion")
    return None if value is None or isinstance(value, str) else float(value)


def label_metrics(labels: GraspLabels, progress: Callable[[int], object] | None = None
                  ) -> Any:
    """The grasp-matrix metrics (:func:`~forceclosure.analysis.metrics.grasp_metrics`) of every
    contact pair of ``labels``, at its ``meta`` friction, contact model and torsion.

    All grasps at once (one batched SVD), the hull volumes one Qhull call a grasp (about a
    millisecond), in chunks of :data:`CHUNK` with ``progress`` called after each. A hard
    pair's volume is 0 (its generators do not span the wrench space), its ``sigma_min`` 0.

    Examples
    --------
    Soft pads on the cube: the pinches are head-on or tilted, every one of rank 6.

    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=5, collision=False)
    >>> m = label_metrics(labels)
    >>> len(m), bool(np.all(m.sigma_min > 0)), bool(np.all(m.volume > 0))
    (5, True, True)
    """
    from ..analysis.metrics import GraspMetrics, grasp_metrics

    meta = labels.meta
    torsion = torsion_of(labels)
    parts = []
    for lo in range(0, len(labels), CHUNK):
        part = slice(lo, min(len(labels), lo + CHUNK))
        parts.append(grasp_metrics(labels.points[part], labels.normals[part], mu=meta["mu"],
                                   model=meta["contact"],
                                   torsion=np.nan if torsion is None else
                                   torsion if np.ndim(torsion) == 0 else torsion[part]))
        if progress is not None:
            progress(part.stop - part.start)
    if not parts:
        return GraspMetrics(np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 3)),
                            np.zeros(0))
    return GraspMetrics(*(np.concatenate([getattr(p, f) for p in parts]) for f in (
        "sigma_min", "sigma_max", "isotropy", "volume", "reference", "length_scale")))


def label_task(labels: GraspLabels, wrench: ArrayLike, f_max: float, edges: int = 8,
               progress: Callable[[int], object] | None = None
               ) -> tuple[NDArray[np.int8], NDArray[np.float64], NDArray[np.float64]]:
    """The task-wrench test (:func:`~forceclosure.analysis.task.resist_wrench_batch`) of every
    contact pair of ``labels``: ``(task_verdict, task_spare, task_spare_upper)``.

    ``wrench`` is the external wrench on the object, torque about the origin of the
    object's frame (e.g. :func:`~forceclosure.analysis.task.gravity_wrench`); each jaw presses with
    a normal force of at most ``f_max``. Every grasp is tested, force-closure or not: a
    grasp that is not force-closure may still resist one particular wrench (a pinch
    whose line passes through the centre of mass holds the weight without closing).
    Two linear programs a grasp, stacked :data:`~forceclosure.analysis.task.BATCH` grasps to a
    HiGHS call (about 0.5 ms a grasp).

    Examples
    --------
    The 2-unit cube, mass 1 under g = 10 along -z, pads of friction 0.3 pressing at most
    1: friction holds at most 2 · 0.3 · 1 and a pad below at most 1, short of 10.

    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=3, collision=False)
    >>> from forceclosure.analysis.task import gravity_wrench
    >>> w = gravity_wrench(1.0, [0, 0, 0], g=[0, 0, -10])
    >>> code, spare, upper = label_task(labels, w, f_max=1.0)
    >>> code.tolist(), bool(np.all(spare <= upper + 1e-12)), bool(np.all(upper < 1))
    ([0, 0, 0], True, True)
    """
    from ..analysis.task import resist_wrench_batch

    meta = labels.meta
    return resist_wrench_batch(labels.points, labels.normals, wrench, mu=meta["mu"],
                               model=meta["contact"], torsion=torsion_of(labels),
                               f_max=f_max, edges=edges, progress=progress)
