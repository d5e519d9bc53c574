"""The task-wrench test: does a grasp resist a given wrench with bounded finger forces?

:func:`resist_wrench` asks whether the fingers can hold an object against
an external wrench ``w`` (for instance gravity, :func:`gravity_wrench`), each
finger pressing with a normal force of at most ``f_max``, and with how much
to spare: the largest scale ``s`` such that ``s · w`` is resisted. It is a
linear program (scipy's HiGHS) over the contacts' generating wrenches:

    maximise s  subject to  W λ + s w = 0,  Σ_{j ∈ finger i} λ_j (-f_j · n_i) ≤ f_max,
    λ ≥ 0, s ≥ 0,

with forces in physical units, torques about ``reference`` (the object's
origin by default). Circular friction cones cannot go into a linear
program, so each is replaced by a pyramid of ``edges`` edges, twice:

* **inscribed** (the pyramid inside the cone): ``spare``. The forces it
  allows are real forces, so ``spare`` is a **lower bound** on the true
  value and ``spare >= 1`` proves the grasp holds. The answer is
  conservative: it errs towards "does not hold", never the other way.
* **circumscribed** (the pyramid around the cone): ``spare_upper``, an upper
  bound; ``spare_upper < 1`` proves the grasp does not hold.

In between, the verdict is ``undecided`` (more ``edges`` narrow the gap,
by a factor of about ``cos(π/edges)``). Planar cones are exact: both agree.
A soft finger carries the library's torque about its normal: unbounded for
the paper's soft finger (``torsion`` None or NaN), else at most
``torsion`` times its normal force.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from numbers import Real

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..contacts import MAX_COORDINATE, Cone, primitive_wrenches
from ..errors import ForceClosureError, InputError, shown

__all__ = ["BATCH", "TASK_CODES", "TASK_VERDICTS", "TaskWrench", "gravity_wrench", "resist_wrench",
           "resist_wrench_batch"]

#: The task verdicts in the order of their codes in :func:`resist_wrench_batch`
#: (``TASK_VERDICTS[code]``: 0 fails, 1 undecided, 2 resists).
TASK_VERDICTS = ("fails", "undecided", "resists")
#: Each task verdict's code.
TASK_CODES = {v: c for c, v in enumerate(TASK_VERDICTS)}


@dataclass(frozen=True, eq=False)
class TaskWrench:
    """Whether a grasp resists a wrench with bounded finger forces (:func:`resist_wrench`).

    Attributes
    ----------
    verdict : str
        ``"resists"`` (proved with the inscribed pyramids: ``spare >= 1``),
        ``"fails"`` (proved with the circumscribed ones: ``spare_upper < 1``)
        or ``"undecided"`` (between the two; use more ``edges``).
    spare : float
        The largest ``s`` such that ``s · wrench`` is resisted with the
        inscribed pyramids: a lower bound for the true cones (``inf``: any
        multiple is, e.g. a pure torque about a soft finger's normal).
    spare_upper : float
        The same with the circumscribed pyramids: an upper bound.
    forces : (k, d) array
        Contact forces (on the object) resisting ``spare · wrench``,
        inscribed pyramids; NaN when ``spare`` is 0 or ``inf``.
    torsion : (k,) array
        Torque of each contact about its outward normal, likewise (0 for
        hard and frictionless contacts).
    wrench : (D,) array
        The wrench tested, ``(force, torque about reference)``.
    reference : (d,) array
    f_max : float
    edges : int
    """

    verdict: str
    spare: float
    spare_upper: float
    forces: NDArray[np.float64]
    torsion: NDArray[np.float64]
    wrench: NDArray[np.float64]
    reference: NDArray[np.float64]
    f_max: float
    edges: int

    @property
    def resists(self) -> bool:
        """True when the grasp is proved to resist the wrench (``spare >= 1``)."""
        return self.verdict == "resists"


def gravity_wrench(mass: float, center_of_mass: ArrayLike, g: ArrayLike = (0.0, 0.0, -9.81),
                   reference: ArrayLike | None = None) -> NDArray[np.float64]:
    """The wrench of gravity on a body: ``(m g, (c - reference) × m g)``, about ``reference``
    (default the origin).

    Examples
    --------
    >>> (gravity_wrench(2.0, [1, 0, 0], g=[0, 0, -10]) + 0.0).tolist()
    [0.0, 0.0, -20.0, 0.0, 20.0, 0.0]
    """
    if isinstance(mass, bool) or not isinstance(mass, Real) or not _finite(mass) \
            or mass < 0:
        raise InputError(f"mass must be a finite number >= 0, got {shown(mass, 80)}")
    c = _finite_vector(center_of_mass, 3, "center_of_mass")
    g_ = _finite_vector(g, 3, "g")
    ref = np.zeros(3) if reference is None else _finite_vector(reference, 3, "reference")
    with np.errstate(over="ignore", invalid="ignore"):
        force = float(mass) * g_
        wrench = np.concatenate([force, np.cross(c - ref, force)])
    if not np.all(np.isfinite(wrench)):
        raise InputError(f"mass {float(mass):g} under g {g_.tolist()} (torque about the "
                         "reference): the wrench overflows")
    return wrench


def _finite(value: Real) -> bool:
    """Whether a real number is finite as a float (an int past float's range is not)."""
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


def _finite_vector(value: ArrayLike, n: int, name: str) -> NDArray[np.float64]:
    """``n`` finite numbers, or one line naming ``name``."""
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be {n} finite numbers, got {shown(value, 80)}") from None
    if v.shape != (n,) or not np.all(np.isfinite(v)):
        raise InputError(f"{name} must be {n} finite numbers, got {shown(v.tolist(), 80)}")
    return v


def _max_scale(W: NDArray, normal_force: NDArray, owner: NDArray, k: int, w: NDArray,
               f_max: float) -> tuple[float, NDArray | None]:
    """The LP of the module's docstring: ``(s*, λ)`` (``λ`` None when unbounded).

    Solved for the unit task (``w`` over its largest component, forces at most 1), whose
    coefficients HiGHS takes whatever the units (a mass of 1e100 is not a model error);
    ``s*`` and ``λ`` scale back exactly: ``s*(w, f) = s*(w / |w|∞, 1) · f / |w|∞``."""
    big = float(np.max(np.abs(w)))
    s, lam = _max_scale_unit(W, normal_force, owner, k, w / big)
    return s * (f_max / big), None if lam is None else lam * f_max


def _max_scale_unit(W: NDArray, normal_force: NDArray, owner: NDArray, k: int, w: NDArray,
                    f_max: float = 1.0) -> tuple[float, NDArray | None]:
    from scipy.optimize import linprog

    m = W.shape[1]
    c = np.zeros(m + 1)
    c[-1] = -1.0
    A_eq = np.hstack([W, w[:, None]])
    A_ub = np.zeros((k, m + 1))
    for i in range(k):
        A_ub[i, :m] = np.where(owner == i, normal_force, 0.0)
    res = linprog(c, A_ub=A_ub, b_ub=np.full(k, f_max), A_eq=A_eq, b_eq=np.zeros(len(w)),
                  bounds=[(0, None)] * (m + 1), method="highs")
    if res.status == 3:
        return math.inf, None
    if res.status != 0:
        raise ForceClosureError(f"the task-wrench LP failed: {res.message}")
    return max(0.0, float(res.x[-1])), res.x[:m]



def _task(wrench: ArrayLike, f_max: float, reference: ArrayLike | None, d: int
          ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The task's wrench and torque reference, checked (``d``: 2 planar, 3 spatial)."""
    D = 3 if d == 2 else 6
    try:
        w = np.asarray(wrench, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"wrench must be {D} numbers") from None
    if w.shape != (D,) or not np.all(np.isfinite(w)):
        raise InputError(f"wrench must be {D} finite numbers (force, torque), got shape "
                         f"{w.shape}")
    if not np.any(w):
        raise InputError("wrench is zero: any grasp resists it, there is nothing to test")
    if isinstance(f_max, bool) or not isinstance(f_max, Real) or not _finite(f_max) \
            or f_max <= 0:
        raise InputError(f"f_max must be a finite positive number, got {shown(f_max, 80)}")
    ratio = float(f_max) / float(np.max(np.abs(w)))
    if not 1e-150 <= ratio <= 1e150:
        raise InputError(f"f_max {float(f_max):g} and the wrench's largest component "
                         f"{float(np.max(np.abs(w))):g} are more than 1e150 apart; rescale "
                         "them (the spare is their ratio's multiple)")
    ref = np.zeros(d) if reference is None else _finite_vector(reference, d, "reference")
    if np.abs(ref).max(initial=0.0) > MAX_COORDINATE:
        raise InputError(f"reference must be within {MAX_COORDINATE:g} of the origin")
    return w, ref

def resist_wrench(points: ArrayLike, normals: ArrayLike, wrench: ArrayLike, *,
                  mu: ArrayLike = 0.0, model: str | Sequence[str] = "soft",
                  torsion: ArrayLike | None = None, f_max: float = 1.0,
                  reference: ArrayLike | None = None, edges: int = 8) -> TaskWrench:
    """Whether ``k`` contacts resist the external ``wrench``, normal forces at most ``f_max``.

    Parameters
    ----------
    points, normals : (k, d) arrays
        Contact points and outward normals of one grasp (``d`` = 2 or 3).
    wrench : (D,) array
        The external wrench on the object, ``(force, torque about
        reference)``: ``D`` = 6 in space (3 in the plane, ``(fx, fy, tau)``);
        e.g. :func:`gravity_wrench`. Not zero.
    mu, torsion : numbers or (k,) arrays
        Friction and torsional coefficients (``torsion`` None or NaN: a soft
        finger's torque is not bounded by its normal force).
    model : str or sequence of k str
        ``"soft"`` (default), ``"hard"`` or ``"frictionless"``.
    f_max : float
        Bound on each finger's normal force (force units of ``wrench``).
    reference : (d,) array, optional
        The point the wrench's torque is about (default the origin).
    edges : int
        Edges of the pyramids standing in for spatial friction cones.

    Returns
    -------
    TaskWrench

    References
    ----------
    .. [1] C. Borst, M. Fischer and G. Hirzinger, "Grasp planning: how to choose a
       suitable task wrench space", *Proc. IEEE ICRA*, 2004
    .. [2] Z. Li and S. S. Sastry, "Task-oriented optimal grasping by multifingered
       robot hands", *IEEE J. Robotics and Automation* 4(1):32-44, 1988

    Examples
    --------
    Two soft pads squeezing a 2-unit box across x, friction 0.5, at most 10 N
    each, against the 4 N weight of the box along -z: friction holds up to
    2 · 0.5 · 10 = 10 N, so the spare is 10 / 4 = 2.5 (here the pyramids
    have an edge along z, so the lower bound is exact):

    >>> P = [[-1, 0, 0], [1, 0, 0]]
    >>> N = [[-1, 0, 0], [1, 0, 0]]
    >>> t = resist_wrench(P, N, gravity_wrench(0.4, [0, 0, 0], g=[0, 0, -10]),
    ...                   mu=0.5, f_max=10.0)
    >>> t.verdict, round(t.spare, 6), t.spare_upper > t.spare
    ('resists', 2.5, True)
    """
    from .batch_analysis import validate_grasps

    try:
        P = np.asarray(points, dtype=float)
        N_ = np.asarray(normals, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError("points and normals must be arrays of numbers") from None
    if P.ndim != 2:
        raise InputError(f"points must have shape (k, 2 or 3) for one grasp, got {P.shape}")
    k = len(P)
    try:
        mu_ = np.broadcast_to(np.asarray(mu, dtype=float), (k,))[None]
        tors_ = None if torsion is None else np.broadcast_to(
            np.asarray(torsion, dtype=float), (k,))[None]
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"mu and torsion must be numbers or {k} numbers (one per contact)"
                         ) from None
    grasps = validate_grasps(P[None], N_[None], mu_, model, tors_)
    d = P.shape[1]
    w, ref = _task(wrench, f_max, reference, d)
    P, N_ = grasps.points[0], grasps.normals[0]
    scale = float(np.max(np.linalg.norm(P - ref, axis=1)))
    scale = scale if scale > 1e-12 * max(1.0, float(np.max(np.abs(P)))) else 1.0
    w_scaled = np.concatenate([w[:d], w[d:] / scale])
    results = []
    for fit in ("inscribed", "circumscribed"):
        cone = Cone(edges, fit)
        blocks = [primitive_wrenches(P[i][None], N_[i][None], m, grasps.mu[0, i][None],
                                     grasps.torsion[0, i][None], ref[None],
                                     np.array([scale]), cone)[0]
                  for i, m in enumerate(grasps.models)]
        W = np.concatenate(blocks, axis=1)
        owner = np.concatenate([np.full(b.shape[1], i) for i, b in enumerate(blocks)])
        normal_force = -np.einsum("dj,jd->j", W[:d], N_[owner])
        results.append((_max_scale(W, normal_force, owner, k, w_scaled, float(f_max)), W,
                        owner))
    (spare, lam), W, owner = results[0]
    spare_upper = results[1][0][0]
    forces = np.full((k, d), np.nan)
    tors = np.full(k, np.nan)
    if lam is not None and spare > 0:
        for i in range(k):
            own = W[:, owner == i] @ lam[owner == i]
            forces[i] = own[:d]
            if d == 3:
                arm = np.cross(P[i] - ref, own[:3]) / scale
                tors[i] = float((own[3:] - arm) @ N_[i]) * scale
            else:
                tors[i] = 0.0
    verdict = "resists" if spare >= 1 else "fails" if spare_upper < 1 else "undecided"
    return TaskWrench(verdict, spare, spare_upper, forces, tors, w, ref, float(f_max), edges)


#: Grasps per stacked linear program in :func:`resist_wrench_batch`.
BATCH = 128


def _stacked_scales(W: NDArray, normal_force: NDArray, owner: NDArray, k: int, w: NDArray,
                    f_max: float) -> NDArray | None:
    """``s*`` of ``n`` independent LPs (``W`` ``(n, D, m)``, ``w`` ``(n, D)``) stacked
    block-diagonally into one: maximising ``Σ s_g`` over separate blocks maximises each
    ``s_g``. None when the stacked LP is not solved to optimality (e.g. one block is
    unbounded): the caller solves the blocks one at a time. Solved for unit tasks, as
    :func:`_max_scale`."""
    from scipy.optimize import linprog
    from scipy.sparse import block_diag

    big = np.max(np.abs(w), axis=1)
    w = w / big[:, None]
    back = f_max / big
    f_max = 1.0
    n, D, m = W.shape
    c = np.zeros((n, m + 1))
    c[:, -1] = -1.0
    A_eq = block_diag([np.hstack([W[g], w[g][:, None]]) for g in range(n)], format="csr")
    rows = np.zeros((n, k, m + 1))
    for i in range(k):
        rows[:, i, :m] = np.where(owner == i, normal_force, 0.0)
    A_ub = block_diag(list(rows), format="csr")
    res = linprog(c.ravel(), A_ub=A_ub, b_ub=np.full(n * k, f_max), A_eq=A_eq,
                  b_eq=np.zeros(n * D), bounds=(0, None), method="highs")
    if res.status != 0:
        return None
    return np.maximum(0.0, res.x.reshape(n, m + 1)[:, -1]) * back


def resist_wrench_batch(points: ArrayLike, normals: ArrayLike, wrench: ArrayLike, *,
                        mu: float = 0.0, model: str | Sequence[str] = "soft",
                        torsion: float | None = None, f_max: float = 1.0,
                        reference: ArrayLike | None = None, edges: int = 8,
                        progress: Callable[[int], object] | None = None
                        ) -> tuple[NDArray[np.int8], NDArray[np.float64], NDArray[np.float64]]:
    """:func:`resist_wrench` for ``N`` grasps (``(N, k, d)``) and one wrench: the verdict
    codes (:data:`TASK_CODES`: 0 fails, 1 undecided, 2 resists), ``spare`` and
    ``spare_upper``, each ``(N,)``.

    The same two LPs a grasp as :func:`resist_wrench`, the generators of all grasps built
    at once and :data:`BATCH` grasps' LPs stacked block-diagonally into one HiGHS call
    (the blocks share no variable, so maximising the sum of the scales maximises each);
    a stacked LP that HiGHS does not solve to optimality (a block unbounded: ``inf``, e.g.
    a pure torque about a soft finger's normal) is solved again grasp by grasp.
    ``progress`` is called with the number of grasps done after each stack.

    Examples
    --------
    The box of :func:`resist_wrench`'s example, and the same pads ten times weaker:

    >>> P = [[[-1, 0, 0], [1, 0, 0]]] * 2
    >>> N = [[[-1, 0, 0], [1, 0, 0]]] * 2
    >>> w = gravity_wrench(0.4, [0, 0, 0], g=[0, 0, -10])
    >>> code, spare, upper = resist_wrench_batch(P, N, w, mu=0.5, f_max=10.0)
    >>> code.tolist(), spare.round(6).tolist()
    ([2, 2], [2.5, 2.5])
    >>> resist_wrench_batch(P, N, w, mu=0.5, f_max=1.0)[0].tolist()
    [0, 0]
    """
    from .batch_analysis import validate_grasps

    grasps = validate_grasps(points, normals, mu, model, torsion)
    P, N_ = grasps.points, grasps.normals
    n, k, d = P.shape
    w, ref = _task(wrench, f_max, reference, d)
    code = np.zeros(n, np.int8)
    spare, upper = np.zeros(n), np.zeros(n)
    for lo in range(0, n, BATCH):
        part = slice(lo, min(n, lo + BATCH))
        Pc, Nc = P[part], N_[part]
        b = len(Pc)
        scale = np.max(np.linalg.norm(Pc - ref, axis=2), axis=1)
        big = np.maximum(1.0, np.max(np.abs(Pc), axis=(1, 2)))
        scale = np.where(scale > 1e-12 * big, scale, 1.0)
        ws = np.concatenate([np.broadcast_to(w[:d], (b, d)), w[d:][None] / scale[:, None]],
                            axis=1)
        found = []
        for fit in ("inscribed", "circumscribed"):
            cone = Cone(edges, fit)
            blocks = [primitive_wrenches(Pc[:, i], Nc[:, i], m, grasps.mu[part, i],
                                         grasps.torsion[part, i],
                                         np.broadcast_to(ref, (b, d)), scale, cone)
                      for i, m in enumerate(grasps.models)]
            W = np.concatenate(blocks, axis=2)
            owner = np.concatenate([np.full(x.shape[2], i) for i, x in enumerate(blocks)])
            normal_force = -np.einsum("gdj,gjd->gj", W[:, :d], Nc[:, owner])
            found.append(_stacked_scales(W, normal_force, owner, k, ws, float(f_max)))
        if found[0] is None or found[1] is None:
            for g in range(b):
                t = resist_wrench(Pc[g], Nc[g], w, mu=grasps.mu[lo + g],
                                  model=grasps.models, torsion=grasps.torsion[lo + g],
                                  f_max=f_max, reference=ref, edges=edges)
                spare[lo + g], upper[lo + g] = t.spare, t.spare_upper
        else:
            spare[part], upper[part] = found
        if progress is not None:
            progress(b)
    code[:] = np.where(spare >= 1, TASK_CODES["resists"],
                       np.where(upper < 1, TASK_CODES["fails"], TASK_CODES["undecided"]))
    return code, spare, upper
