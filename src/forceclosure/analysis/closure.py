"""The force-closure test: Theorems 1–3 of Nguyen (1988), sound and explained.

**Theorem 1 (vector closure).** Vectors ``W`` (``d x m``) positively span
``R^d`` iff ``rank W = d`` and some strictly positive combination of them is
zero. A grasp is force-closure iff its generating wrenches are vector closed
(``d = 3`` planar, ``6`` spatial).

:func:`vector_closure` decides both halves with one tolerance ``tol``:

* the rank, from the singular values of the unit-normalised columns;
* the margin, from one linear program: maximise ``s`` subject to
  ``W lam = 0``, ``sum(lam) = 1``, ``lam_i >= s``; the margin is ``m s*``
  (1 for perfectly balanced columns, ``<= 0`` when no strictly positive
  combination exists).

The verdict is three-way. ``closure`` needs the smallest singular value
ratio and the margin both above ``tol`` *and* a certificate that survives a
check independent of the LP solver: the solver's weights, corrected onto the
exact null space of ``W``, stay strictly positive. ``none`` needs a proof too:
a numerical rank below ``d`` (a twist reciprocal to every wrench), or a twist
strictly repelling every wrench by more than ``tol``. Anything in between is
``marginal``: within ``tol`` of the boundary, never called closure.

Theorems 2 and 3 split the question: force-direction closure (the forces
positively span all directions) and torque closure (positive combinations of
the wrenches make every pure torque). A grasp is force-closure iff both hold,
so when it is not, the result says which failed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import partial

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linprog

from ..contacts import (
    Cone,
    Contact,
    WrenchSet,
    check_grasp,
    fixed_cone,
    frame,
    generating_wrenches,
    model_codes,
    own_frame,
    unit_rows,
)
from ..errors import InputError
from ..geometry import cones
from ..tolerance import TOLERANCE
from ..verdicts import Verdict
from .motion import Motion, motion_of, shift_twist

__all__ = ["EXACT_CONE_EDGES", "FRICTION_CAP", "TOLERANCE", "TORSION_MAX", "Analysis",
           "VectorClosure", "Verdict", "analyze", "analyze_explained", "check_rtol",
           "check_tolerance", "decide", "force_direction_closure", "torque_closure",
           "vector_closure"]

#: Friction above this proves closure only as this much does (friction is
#: monotone: a grasp closed with less is closed with more), and refutes it
#: only as the closed half-space does (the limit of any friction). Between
#: the two a grasp is ``marginal``: its cones' half-angles are within
#: ``atan(1 / FRICTION_CAP)`` (1e-4 rad) of the half-space. Above it the cone's
#: edges ``-n ± mu t`` are numerically the tangent line (at 1e16 exactly).
FRICTION_CAP = 1e4

#: Largest torsional coefficient accepted, relative to the grasp's own size
#: (a torsional friction radius a million times the grasp is not a contact
#: patch; beyond it a wrench's force part would vanish in its torque).
TORSION_MAX = 1e6

#: Pyramid sizes tried, in turn, to bracket an exact circular friction cone.
EXACT_CONE_EDGES = (8, 16, 32, 64, 128, 256)


#: The kernels' codes of contact models (their verdicts' codes: :class:`VerdictCode`).
@dataclass(frozen=True, eq=False)
class VectorClosure:
    """Theorem 1 for one set of vectors, with its certificate.

    Attributes
    ----------
    verdict : Verdict
    rank : int
        Numerical rank of the vectors.
    sigma_ratio : float
        Smallest over largest singular value of the unit-normalised vectors
        (0 when fewer vectors than dimensions).
    margin : float or None
        ``m s*`` from the LP (see the module); None when the rank is
        deficient (no LP is run) or no affine combination of the vectors is
        zero at all.
    weights : array or None
        For ``closure``: strictly positive weights, summing to 1, that
        combine the (original, unnormalised) vectors to zero.
    twist : array or None
        For ``none`` and ``marginal``: ``t`` with ``|t|_inf = 1`` and
        ``W^T t >= 0`` (``none``), or as nearly so as possible (``marginal``),
        laid out like the vectors (for wrenches: force slots hold a velocity,
        torque slots an angular velocity; see :func:`motion.shift_twist`).
    repelling : float
        ``min_i w_i . t / |w_i|`` for that twist: > 0 strictly repelling,
        0 reciprocal.
    reason : str
        One sentence: why this verdict.
    """

    verdict: Verdict
    rank: int
    sigma_ratio: float
    margin: float | None
    weights: NDArray[np.float64] | None
    twist: NDArray[np.float64] | None
    repelling: float
    reason: str

    def __bool__(self) -> bool:
        """True iff the verdict is ``closure`` (``marginal`` and ``none`` are False)."""
        return self.verdict is Verdict.CLOSURE


def check_tolerance(tol: object, name: str = "tol") -> float:
    """``tol`` as a float, refused unless it is a number with 0 <= tol < 1.

    Examples
    --------
    >>> check_tolerance(1e-6)
    1e-06
    """
    if isinstance(tol, bool) or not isinstance(tol, int | float | np.floating | np.integer):
        raise InputError(f"'{name}' must be a number, got {tol!r}")
    if not 0.0 <= float(tol) < 1.0:
        raise InputError(f"'{name}' must be >= 0 and < 1, got {tol!r}")
    return float(tol)


def check_rtol(rtol: object) -> float:
    """A bisection's relative precision, refused unless 1e-15 <= rtol < 1 (below 1e-15
    the bracket could stop shrinking between two neighbouring floats)."""
    if isinstance(rtol, bool) or not isinstance(rtol, int | float | np.floating | np.integer):
        raise InputError(f"'rtol' must be a number, got {rtol!r}")
    if not 1e-15 <= float(rtol) < 1.0:
        raise InputError(f"'rtol' must be >= 1e-15 and < 1, got {rtol!r}")
    return float(rtol)


def _fmt(x: float | None) -> str:
    """A margin for people: three significant digits, ``n/a`` when undefined."""
    if x is None or not math.isfinite(x):
        return "n/a"
    return "0" if abs(x) < 5e-16 else f"{x:.3g}"


def _lp(c, A_ub=None, b_ub=None, A_eq=None, b_eq=None, bounds=None):
    res = linprog(c, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds, method="highs")
    return res if res.status == 0 else None


def _balance(U: NDArray[np.float64]) -> tuple[float | None, NDArray[np.float64] | None]:
    """max s s.t. U lam = 0, sum lam = 1, lam >= s; returns (s*, lam*)."""
    d, m = U.shape
    c = np.zeros(m + 1)
    c[0] = -1.0
    A_eq = np.zeros((d + 1, m + 1))
    A_eq[:d, 0] = U.sum(axis=1)
    A_eq[:d, 1:] = U
    A_eq[d, 0] = m
    A_eq[d, 1:] = 1.0
    b_eq = np.zeros(d + 1)
    b_eq[d] = 1.0
    res = _lp(c, A_eq=A_eq, b_eq=b_eq, bounds=[(None, 1.0)] + [(0, None)] * m)
    if res is None:
        return None, None
    s = float(res.x[0])
    return s, s + res.x[1:]


def _separate(U: NDArray[np.float64]) -> NDArray[np.float64]:
    """The twist that best repels every column: max z s.t. U^T t >= z, |t|_inf <= 1."""
    d, m = U.shape
    c = np.zeros(d + 1)
    c[-1] = -1.0
    A_ub = np.hstack([-U.T, np.ones((m, 1))])
    res = _lp(c, A_ub=A_ub, b_ub=np.zeros(m), bounds=[(-1, 1)] * d + [(None, None)])
    return np.zeros(d) if res is None else res.x[:d]


def _certify(U: NDArray[np.float64], lam: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """Weights ``lam' > 0`` with ``U lam' = 0`` up to rounding, or None.

    ``lam`` solves ``U lam = r`` with a small residual ``r``. For full-rank
    ``U`` the minimum-norm correction ``delta = -U^+ r`` puts ``lam + delta``
    in the exact null space; if ``|delta|`` is below ``min(lam)`` the
    corrected weights are still strictly positive, a certificate that does
    not depend on the LP solver's tolerances.
    """
    lam_c = lam - np.linalg.lstsq(U, U @ lam, rcond=None)[0]
    sigma_min = np.linalg.svd(U, compute_uv=False)[-1]
    # what rounding leaves, and the further correction it would need, stays small
    leftover = np.linalg.norm(U @ lam_c) / sigma_min
    if lam_c.min() <= max(0.5 * lam.min(), 2 * leftover):
        return None
    return lam_c


def _null_twist(U: NDArray[np.float64]) -> NDArray[np.float64]:
    """A unit-max twist reciprocal to ``U``, its largest component +1.

    The SVD fixes a null vector only up to sign, and LAPACK builds differ in
    the sign they return; dividing by the largest component makes it one.
    """
    # only the left singular vectors are needed: full ones only when there are fewer
    # columns than rows (else the m x m right factor would cost m^2 memory)
    u = np.linalg.svd(U, full_matrices=U.shape[1] < U.shape[0])[0][:, -1]
    return u / u[np.argmax(np.abs(u))]


def vector_closure(W: ArrayLike, tol: float = TOLERANCE,
                   two_sided: ArrayLike | None = None) -> VectorClosure:
    """Decide whether vectors positively span their space (Theorem 1).

    Parameters
    ----------
    W : (d, m) array
        The vectors, as columns (for a grasp, its generating wrenches).
    tol : float
        The tolerance of the ``marginal`` band (see the module).
    two_sided : (m,) bool array, optional
        Columns that come in opposite pairs by construction (a soft finger's
        pure torques). Every twist is at best reciprocal to them, so they are
        quotiented out: Theorem 1 is decided for the other columns projected
        onto the orthogonal complement of their span, and the certificates
        lifted back. Without this a grasp they are part of could never be
        proved ``none``.

    Returns
    -------
    VectorClosure

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, §2.2, Theorem 1
    .. [2] A. J. Goldman and A. W. Tucker, "Polyhedral convex cones", in *Linear
       Inequalities and Related Systems*, Annals of Math. Studies 38, 1956 (Lemma 6)

    Examples
    --------
    The vertices of a triangle around the origin positively span the plane;
    three vectors in the upper half-plane do not:

    >>> r = vector_closure([[1, -1, 0], [-1, -1, 2]])
    >>> r.verdict.value, r.rank
    ('closure', 2)
    >>> vector_closure([[1, -1, 0], [1, 1, 2]]).verdict.value
    'none'
    """
    try:
        W = np.asarray(W, dtype=float)
    except (TypeError, ValueError):
        raise InputError("wrench matrix must be an array of numbers") from None
    if W.ndim != 2 or W.shape[0] == 0:
        raise InputError(f"wrench matrix must be 2-D (d x m, d >= 1), got shape {W.shape}")
    if not np.all(np.isfinite(W)):
        raise InputError("wrench matrix has a non-finite entry")
    check_tolerance(tol)
    d = W.shape[0]
    units, norms = unit_rows(W.T)
    if not np.all(np.isfinite(norms)):  # a column longer than the largest float
        units, norms = unit_rows(W.T / np.max(np.abs(W)))  # only ratios of lengths matter
    keep = norms > 1e-12 * max(1.0, float(norms.max(initial=0.0)))
    U = units[keep].T
    pairs = (np.zeros(W.shape[1], bool) if two_sided is None
             else np.asarray(two_sided, bool))[keep]
    m = U.shape[1]
    t: NDArray[np.float64]
    if m == 0:
        t = np.zeros(d)
        t[0] = 1.0
        return VectorClosure(Verdict.NONE, 0, 0.0, None, None, t, 0.0,
                             "no nonzero vectors: nothing resists any motion")
    sv = np.linalg.svd(U, compute_uv=False)
    rank = int(np.sum(sv > max(d, m) * np.finfo(float).eps * sv[0]))
    ratio = float(sv[d - 1] / sv[0]) if m >= d else 0.0
    if m == d and rank == d:  # the counting fact, answered before any LP
        t = np.linalg.solve(U.T, np.ones(d)).astype(float)  # every vector does work 1 on t
        t /= np.max(np.abs(t))
        return VectorClosure(Verdict.NONE, rank, ratio, None, None, t, float(np.min(U.T @ t)),
                             f"only {m} vectors; at least {d + 1} are needed")
    if rank < d:  # the first half of Theorem 1 fails; no LP needed
        t = _null_twist(U)
        why = (f"rank {rank} < {d}: the vectors span only a {rank}-dimensional subspace"
               + (f" ({m} vectors; at least {d + 1} are needed)" if m < d + 1 else ""))
        return VectorClosure(Verdict.NONE, rank, ratio, None, None, t,
                             float(np.min(U.T @ t)), why)
    if pairs.any():
        return _modulo_lineality(W, U, keep, norms, pairs, ratio, tol)

    s, lam = _balance(U)
    margin = None if s is None else m * s

    if ratio > tol and margin is not None and lam is not None and margin > tol:
        lam_c = _certify(U, lam)
        if lam_c is not None:
            weights = np.zeros(W.shape[1])
            weights[keep] = lam_c / norms[keep]
            weights /= weights.sum()
            return VectorClosure(Verdict.CLOSURE, rank, ratio, margin, weights, None, -1.0,
                                 f"rank {d} and a strictly positive combination is zero "
                                 f"(margin {_fmt(margin)})")

    t = _separate(U)
    z = float(np.min(U.T @ t)) if np.any(t) else 0.0
    if z > tol:
        why = (f"only {m} vectors; at least {d + 1} are needed" if m < d + 1 else
               "no strictly positive combination is zero: a twist repels every wrench")
        return VectorClosure(Verdict.NONE, rank, ratio, margin, None, t, z, why)
    if ratio <= tol:
        t = _null_twist(U)
        z = float(np.min(U.T @ t))
        why = f"nearly rank-deficient (singular value ratio {ratio:.3g} <= tolerance {tol:g})"
    else:
        why = f"on the boundary: margin {_fmt(margin)} within tolerance {tol:g} of zero"
    return VectorClosure(Verdict.MARGINAL, rank, ratio, margin, None,
                         t if np.any(t) else None, z, why)


def _modulo_lineality(W: NDArray[np.float64], U: NDArray[np.float64],
                      keep: NDArray[np.bool_], norms: NDArray[np.float64],
                      two_sided: NDArray[np.bool_], ratio: float, tol: float) -> VectorClosure:
    """Theorem 1 for a cone with a lineality space ``L`` (two-sided generators).

    ``cone(U) = cone(R) + L`` with ``R`` the one-sided columns, so it is the
    whole space iff the projections of ``R`` onto ``L``'s orthogonal
    complement positively span it. Deciding that reduced problem gives
    robust certificates: twists orthogonal to ``L`` (reciprocal to every
    two-sided generator by construction) and weights lifted back with the
    two-sided pairs absorbing what lies in ``L``.
    """
    d = U.shape[0]
    P, R = U[:, two_sided], U[:, ~two_sided]
    basis, sv, _ = np.linalg.svd(P, full_matrices=P.shape[1] < d)  # d x d left factor
    dim_l = int(np.sum(sv > max(P.shape) * np.finfo(float).eps * sv[0]))
    Q = basis[:, dim_l:]
    if Q.shape[1] > 0 and R.shape[1] > 0:
        sub = vector_closure(Q.T @ R, tol)
    else:  # L is everything (rank is full, checked before): one-sided columns are absorbed
        sub = VectorClosure(Verdict.CLOSURE, 0, 1.0, 1.0,
                            np.full(R.shape[1], 1.0 / max(R.shape[1], 1)), None, -1.0, "")
    if sub.verdict is Verdict.CLOSURE:
        w_r = sub.weights
        assert w_r is not None  # a closure carries its weights
        c = np.linalg.lstsq(P, -(R @ w_r), rcond=None)[0]
        w_p = c + max(0.0, -float(c.min())) + 1.0 / P.shape[1]
        lam = np.zeros(U.shape[1])
        lam[~two_sided], lam[two_sided] = w_r, w_p
        lam /= lam.sum()
        lam_c = _certify(U, lam)
        if lam_c is not None:
            weights = np.zeros(W.shape[1])
            weights[keep] = lam_c / norms[keep]
            weights /= weights.sum()
            return VectorClosure(Verdict.CLOSURE, d, min(ratio, sub.sigma_ratio), sub.margin,
                                 weights, None, -1.0,
                                 f"rank {d} and a strictly positive combination is zero "
                                 f"(margin {_fmt(sub.margin)})")
        sub = VectorClosure(Verdict.MARGINAL, d, sub.sigma_ratio, sub.margin, None, None, 0.0,
                            "the equilibrium weights could not be certified")
    twist = None if sub.twist is None else Q @ sub.twist
    if twist is not None:
        twist = twist / np.max(np.abs(twist))
    return VectorClosure(sub.verdict, d, min(ratio, sub.sigma_ratio), sub.margin, None, twist,
                         sub.repelling, sub.reason)


def _contains(U: NDArray[np.float64], target: NDArray[np.float64]) -> bool:
    """Whether ``target`` is a non-negative combination of the columns of ``U``."""
    m = U.shape[1]
    res = linprog(np.zeros(m), A_eq=U, b_eq=target, bounds=[(0, None)] * m, method="highs")
    return res.status == 0


def force_direction_closure(W: ArrayLike, tol: float = TOLERANCE) -> bool:
    """Theorem 2 / Corollary 1: can the grasp push the object in every direction?

    True iff the force parts of the wrenches positively span the force space
    (with margin ``tol``). Pure torques (zero force part) do not count.

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, §3.1, Theorem 2
       and Corollary 1

    Examples
    --------
    >>> W = [[1, -1, 0, 0], [0, 0, 1, -1], [0, 0, 0, 0]]   # (fx, fy, tau) columns
    >>> force_direction_closure(W)
    True
    """
    W = np.asarray(W, dtype=float)
    k = 2 if W.shape[0] == 3 else 3
    F = W[:k]
    F = F[:, np.linalg.norm(F, axis=0) > 1e-12]
    return F.shape[1] > 0 and vector_closure(F, tol).verdict is Verdict.CLOSURE


def torque_closure(W: ArrayLike) -> bool:
    """Theorem 3 / Corollary 2: do positive combinations make every pure torque?

    True iff ``(0, +e_j)`` and ``(0, -e_j)`` lie in the cone of the wrenches
    for every torque axis ``e_j``.

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, §3.2, Theorem 3
       and Corollary 2

    Examples
    --------
    Two forces along one line make no torque at all:

    >>> torque_closure([[1, -1], [0, 0], [0, 0]])
    False
    """
    W = np.asarray(W, dtype=float)
    d = W.shape[0]
    k = 2 if d == 3 else 3
    U = W / np.maximum(np.linalg.norm(W, axis=0), 1e-300)
    for j in range(k, d):
        for sign in (1.0, -1.0):
            target = np.zeros(d)
            target[j] = sign
            if not _contains(U, target):
                return False
    return True


@dataclass(frozen=True)
class _Explanation:
    """What :class:`Analysis` says beyond the verdict: Theorems 2 and 3, the certificate,
    the motion, the reason (computed by the reference path, on first use)."""

    sigma_ratio: float
    force_direction_closure: bool
    torque_closure: bool
    contact_forces: NDArray[np.float64] | None
    twist: NDArray[np.float64] | None
    motion: Motion | None
    reason: str
    cone: str
    reference: NDArray[np.float64]
    length_scale: float


def _explanation_field(name: str, doc: str) -> property:
    return property(lambda self: getattr(self._explanation, name), doc=doc)


@dataclass(frozen=True, eq=False)
class Analysis:
    """The answer to "is this grasp force-closure?", with its reasons.

    The verdict, rank and margin come first (for point contacts, from the
    compiled kernel: microseconds); the rest is worked out by the reference
    path the first time any of it is read (linear programs: milliseconds).

    Attributes
    ----------
    verdict : Verdict
        ``closure`` / ``marginal`` / ``none``.
    rank : int
        Rank of the generating wrenches (3 planar, 6 spatial when full).
    margin : float or None
        The LP margin of Theorem 1 (see :func:`vector_closure`), in the frame
        ``reference``, ``length_scale``.
    sigma_ratio : float
        Smallest over largest singular value of the normalised wrenches.
    force_direction_closure, torque_closure : bool
        Theorems 2 and 3; both True iff the verdict is ``closure``.
    contact_forces : (k, d) array or None
        For ``closure``: forces, one per contact, in strict equilibrium (the
        certificate; summing to zero force and torque). Contacts with pure
        torques (soft fingers) may also contribute torque.
    twist : array or None
        The unresisted motion (``none``) or the least-resisted one
        (``marginal``), as a twist about the origin in object coordinates.
    motion : Motion or None
        That twist decoded (see :meth:`Motion.describe`).
    reason : str
        Why, in one sentence.
    cone : str
        Which friction cones decided the verdict.
    reference, length_scale :
        The torque reference point and length scale used for the margin.
    """

    verdict: Verdict
    rank: int
    margin: float | None
    _explain: Callable[[], _Explanation] = field(repr=False)

    @property
    def _explanation(self) -> _Explanation:
        # kept in the instance's dict on first reading (no lock: two threads reading at
        # once compute the same thing; an error in the reference path is not kept)
        found = self.__dict__.get("_explained")
        if found is None:
            found = self.__dict__["_explained"] = self._explain()
        return found

    sigma_ratio = _explanation_field("sigma_ratio", "Smallest over largest singular value.")
    force_direction_closure = _explanation_field("force_direction_closure", "Theorem 2.")
    torque_closure = _explanation_field("torque_closure", "Theorem 3.")
    contact_forces = _explanation_field("contact_forces", "The certificate of closure.")
    twist = _explanation_field("twist", "The unresisted (or least-resisted) twist.")
    motion = _explanation_field("motion", "That twist decoded.")
    reason = _explanation_field("reason", "Why, in one sentence.")
    cone = _explanation_field("cone", "Which friction cones decided the verdict.")
    reference = _explanation_field("reference", "The torque reference point of the margin.")
    length_scale = _explanation_field("length_scale", "The length scale of the margin.")

    @property
    def force_closure(self) -> bool:
        """True iff the verdict is ``closure``."""
        return self.verdict is Verdict.CLOSURE

    def __bool__(self) -> bool:
        """``if analyze(grasp):`` reads "if the grasp is force-closure": True iff the verdict
        is ``closure``; a ``marginal`` grasp (within the tolerance of the boundary, not
        certified) and a ``none`` one are False.

        Examples
        --------
        >>> from forceclosure import point_contact
        >>> pinch = [point_contact([x, 0], [x, 0], "hard", 0.5) for x in (-1, 1)]
        >>> bool(analyze(pinch)), bool(analyze(pinch[:1]))
        (True, False)
        """
        return self.force_closure

    def explain(self) -> str:
        """A few lines a person can read: the verdict, what failed, what moves.

        Examples
        --------
        >>> from forceclosure import point_contact
        >>> grasp = [point_contact([x, 0.3, 0.2], [x, 0, 0], "hard", 0.5) for x in (-1, 1)]
        >>> print(analyze(grasp).explain())   # doctest: +NORMALIZE_WHITESPACE
        none: rank 5 < 6: the wrenches span only a 5-dimensional subspace
          torque closure fails (Theorem 3)
          unresisted: rotation in either direction about the axis through (0, 0.3, 0.2)
          with direction (1, 0, 0)
        """
        lines = [f"{self.verdict.value}: {self.reason}"]
        if self.verdict is Verdict.CLOSURE:
            lines.append(f"  margin {_fmt(self.margin)}, rank {self.rank}; {self.cone}")
            return "\n".join(lines)
        failed = [name for ok, name in (
            (self.force_direction_closure, "force-direction closure fails (Theorem 2)"),
            (self.torque_closure, "torque closure fails (Theorem 3)")) if not ok]
        lines.extend(f"  {f}" for f in failed)
        if self.motion is not None:
            label = "unresisted" if self.verdict is Verdict.NONE else "least resisted"
            lines.append(f"  {label}: {self.motion.describe()}")
        return "\n".join(lines)


def _spatial_friction(contacts: Sequence[Contact]) -> bool:
    return contacts[0].dim == 3 and any(c.frictional and c.mu > 0 for c in contacts)


def decide(contacts: Sequence[Contact], cone: str | Cone = "exact", tol: float = TOLERANCE,
           reference: ArrayLike | None = None, length_scale: float | None = None,
           ) -> tuple[VectorClosure, WrenchSet, str]:
    """Theorem 1 for a grasp's contacts, bracketing exact spatial cones.

    With ``cone="exact"`` a spatial grasp with friction is tested with an
    inscribed ``k``-edge pyramid (inside the true cone: its ``closure`` is
    the true cone's) and a circumscribed one (around it: its ``none`` is the
    true cone's), for ``k`` in :data:`EXACT_CONE_EDGES` until one of them
    decides; if none does, the grasp is ``marginal`` (within the friction
    ratio ``cos(pi/256)`` of the boundary).

    The verdict is decided in the grasp's own frame (torques about the
    contacts' centroid, divided by their largest distance from it), so
    ``reference`` and ``length_scale`` are only checked here: however small
    or large, they cannot change it. Friction above :data:`FRICTION_CAP` is
    decided as that documents.

    Returns the deciding :class:`VectorClosure`, its wrench set (in the
    grasp's own frame), and a description of the cones used.
    """
    return _decision(contacts, cone, tol, reference, length_scale)[:3]


def _decision(contacts: Sequence[Contact], cone: str | Cone, tol: float,
              reference: ArrayLike | None, length_scale: float | None,
              ) -> tuple[VectorClosure, WrenchSet, str, list[Contact], Cone, list[bool] | None]:
    """:func:`decide`, also returning the contacts, pyramid and half-space marks that decided."""
    contacts = check_grasp(contacts)
    check_tolerance(tol)
    fixed_cone(cone)
    if reference is not None or length_scale is not None:
        frame(contacts, reference, length_scale)  # refuses a bad frame
    _check_torsion(contacts)
    above = [c.frictional and c.mu > FRICTION_CAP for c in contacts]
    if not any(above):
        vc, ws, label, use = _decide(contacts, cone, tol)
        return vc, ws, label, contacts, use, None
    capped = [Contact(c.points, c.normals, c.model, FRICTION_CAP, c.torsion) if big else c
              for c, big in zip(contacts, above, strict=True)]
    vc, ws, label, use = _decide(capped, cone, tol)  # less friction: its closure is a proof
    if vc.verdict is Verdict.CLOSURE:
        return (vc, ws, f"{label}; friction above {FRICTION_CAP:g} taken as {FRICTION_CAP:g}",
                capped, use, None)
    top, top_ws, top_label, top_use = _decide(contacts, cone, tol, above)  # more: none proves
    if top.verdict is Verdict.NONE:
        return (top, top_ws, f"{top_label}; friction above {FRICTION_CAP:g} taken as the "
                             "half-space", contacts, top_use, above)
    why = (f"friction above {FRICTION_CAP:g}: not closed with {FRICTION_CAP:g}, nor refuted "
           "with half-space cones (within atan(1e-4) of the half-space)")
    return (VectorClosure(Verdict.MARGINAL, vc.rank, vc.sigma_ratio, vc.margin, None, vc.twist,
                          vc.repelling, why), ws,
            f"{label}; friction above {FRICTION_CAP:g} undecided", capped, use, None)


def _check_torsion(contacts: list[Contact]) -> None:
    """Refuse a torsional coefficient above :data:`TORSION_MAX` times the grasp's size."""
    if all(c.torsion is None or c.model != "soft" for c in contacts):
        return
    _, size = frame(contacts)
    for i, c in enumerate(contacts):
        if c.model == "soft" and c.torsion is not None and c.torsion > TORSION_MAX * size:
            raise InputError(f"contact {i + 1}: 'torsion' {c.torsion:g} is more than "
                             f"{TORSION_MAX:g} times the grasp's size {size:.3g}")


def _decide(contacts: list[Contact], cone: str | Cone, tol: float,
            half_space: Sequence[bool] | None = None,
            ) -> tuple[VectorClosure, WrenchSet, str, Cone]:
    """:func:`decide` in the grasp's own frame, ``half_space`` contacts with unbounded
    friction; also returns the pyramid that decided."""
    fixed = fixed_cone(cone)
    if fixed is not None or not _spatial_friction(contacts):
        use = fixed or Cone()
        ws = generating_wrenches(contacts, use, half_space=half_space)
        label = "exact planar cones" if contacts[0].dim == 2 else (
            f"{use}s" if _spatial_friction(contacts) else "no friction cones")
        return vector_closure(ws.wrenches, tol, ws.two_sided), ws, label, use
    for k in EXACT_CONE_EDGES:
        inner_ws = generating_wrenches(contacts, Cone(k, "inscribed"), half_space=half_space)
        inner = vector_closure(inner_ws.wrenches, tol, inner_ws.two_sided)
        if inner.verdict is Verdict.CLOSURE:
            return (inner, inner_ws, f"exact cones (proved with {k}-edge inscribed pyramids)",
                    Cone(k, "inscribed"))
        if (inner.verdict is Verdict.MARGINAL and half_space is None
                and _one_sided(contacts, inner_ws, tol)):
            why = ("every exact cone lies on one side of the turn about the line through "
                   "two contacts: no finer pyramid closes the grasp, none refutes it")
            return (VectorClosure(Verdict.MARGINAL, inner.rank, inner.sigma_ratio,
                                  inner.margin, None, inner.twist, inner.repelling, why),
                    inner_ws,
                    f"exact cones (marginal at {k} edges, on one side of a turn about two "
                    "contacts)",
                    Cone(k, "inscribed"))
        outer_ws = generating_wrenches(contacts, Cone(k, "circumscribed"),
                                       half_space=half_space)
        outer = vector_closure(outer_ws.wrenches, tol, outer_ws.two_sided)
        if outer.verdict is Verdict.NONE:
            return (outer, outer_ws,
                    f"exact cones (refuted with {k}-edge circumscribed pyramids)",
                    Cone(k, "circumscribed"))
    why = (f"within the friction ratio cos(pi/{k}) of the boundary: {k}-edge inscribed "
           f"pyramids do not close the grasp and circumscribed ones do not refute it")
    marginal = VectorClosure(Verdict.MARGINAL, inner.rank, inner.sigma_ratio, inner.margin,
                             None, inner.twist, inner.repelling, why)
    return marginal, inner_ws, f"exact cones (undecided at {k} edges)", Cone(k, "inscribed")


def _one_sided(contacts: list[Contact], ws: WrenchSet, tol: float) -> bool:
    """Whether a turn about two contacts settles the exact cones' ``marginal`` at once
    (:func:`forceclosure.geometry.cones.one_sided`): point contacts, hard or frictionless."""
    if any(c.model == "soft" or len(c.points) != 1 or len(c.normals) != 1
           for c in contacts):
        return False
    return cones.one_sided(np.concatenate([c.points for c in contacts]),
                           np.concatenate([c.normals for c in contacts]),
                           np.array([c.mu for c in contacts]), np.asarray(ws.reference),
                           float(ws.length_scale), len(contacts) * EXACT_CONE_EDGES[-1], tol)


def _translation(W: NDArray[np.float64], tol: float,
                 ) -> tuple[NDArray[np.float64], bool] | None:
    """Where force-direction closure fails (Theorem 2), a pure translation no wrench
    resists, as a twist laid out like ``W``'s rows, and whether its opposite is unresisted
    too; None if the force parts' own test does not prove one (``marginal``).

    It is what a person reads first ("lifted off the table"), where the LP of Theorem 1
    may have found a rotation about a far-away axis: the same certificate, as the force
    parts ``f`` of every wrench do work ``f . v >= 0`` on it and pure torques none.
    """
    k = 2 if W.shape[0] == 3 else 3
    F = W[:k]
    F = F[:, np.linalg.norm(F, axis=0) > 1e-12]
    if F.shape[1] == 0:
        return None
    found = vector_closure(F, tol)
    if found.verdict is not Verdict.NONE or found.twist is None:
        return None
    y = np.zeros(W.shape[0])
    y[:k] = found.twist
    work = (F.T @ found.twist) / np.linalg.norm(W[:, np.linalg.norm(W[:k], axis=0) > 1e-12],
                                                axis=0)
    if work.min() < -tol:  # not a certificate after all (rounding): keep Theorem 1's
        return None
    return y, bool(np.max(np.abs(work)) <= tol)


def _motion(dual: NDArray[np.float64], contacts: list[Contact], both_ways: bool) -> Motion:
    """The motion of a twist found in the grasp's own frame, decoded in units of
    :func:`contacts.binary_unit` (so huge or tiny coordinates neither overflow nor vanish)
    and brought back to the object's coordinates."""
    ref, scale, unit = own_frame(np.concatenate([c.points for c in contacts]))
    if unit < 1.0:  # tiny coordinates are one point: torques about it, in its own units
        ref, scale, unit = ref * unit, 1.0, 1.0
    motion = motion_of(shift_twist(dual, ref, scale), both_ways=both_ways, length_scale=scale,
                       reference=ref)
    if unit == 1.0:
        return motion
    k = 1 if len(motion.twist) == 3 else 3
    twist = motion.twist.copy()
    if motion.kind == "translation":  # |v| = 1: omega is per unit length
        twist[:k] /= unit
    else:  # |omega| = 1: v is a length
        twist[k:] *= unit
    return Motion(motion.kind, twist, None if motion.point is None else motion.point * unit,
                  motion.direction, motion.pitch * unit, motion.both_ways)


def analyze(contacts: Sequence[Contact], *, cone: str | Cone = "exact", tol: float = TOLERANCE,
            reference: ArrayLike | None = None, length_scale: float | None = None) -> Analysis:
    """Is the grasp force-closure? Theorem 1, explained by Theorems 2 and 3.

    Parameters
    ----------
    contacts : sequence of Contact
        The grasp: all planar or all spatial.
    cone : "exact" or Cone
        ``"exact"`` (default) decides spatial friction for true circular
        cones by bracketing (see :func:`decide`); a :class:`Cone` uses that
        fixed pyramid, as other tools do. Planar cones are always exact.
    tol : float
        Width of the ``marginal`` band.
    reference, length_scale :
        Torque reference point and length scale of the margin (default: the
        contacts' centroid and their largest distance from it). They change
        the margin, not the verdict: that is decided in the grasp's own
        frame, whatever they are (:func:`decide`).

    Returns
    -------
    Analysis

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, §2.2, Theorem 1 (the
       verdict); §3, Theorems 2 and 3 (its explanation)
    .. [2] A. J. Goldman and A. W. Tucker, "Polyhedral convex cones", in *Linear
       Inequalities and Related Systems*, Annals of Math. Studies 38, 1956 (Lemma 6)

    Examples
    --------
    Two planar hard fingers squeezing a unit square across its middle
    (Corollary 3 holds: the segment lies inside both friction cones):

    >>> from forceclosure import point_contact
    >>> grasp = [point_contact([-1, 0], [-1, 0], "hard", 0.3),
    ...          point_contact([1, 0.2], [1, 0], "hard", 0.3)]
    >>> analyze(grasp).verdict
    <Verdict.CLOSURE: 'closure'>
    """
    contacts = check_grasp(contacts)
    if reference is None and length_scale is None:
        fast = _compiled(contacts, cone, tol)
        if fast is not None:
            verdict, rank, margin = fast
            return Analysis(verdict, rank, margin,
                            partial(_explained, contacts, cone, tol, verdict))
    verdict, rank, margin, explanation = _analysis(contacts, cone, tol, reference,
                                                   length_scale)
    return Analysis(verdict, rank, margin, partial(_given, explanation))


def analyze_explained(contacts: Sequence[Contact], *, cone: str | Cone = "exact",
                      tol: float = TOLERANCE, reference: ArrayLike | None = None,
                      length_scale: float | None = None) -> Analysis:
    """:func:`analyze` with everything worked out now, by the reference path alone.

    For callers that read the whole explanation of a few grasps (the command
    line's grasp files): the compiled kernel would only add loading numba
    (about a second per process) to the linear programs the explanation needs.

    Examples
    --------
    >>> from forceclosure import point_contact
    >>> a = analyze_explained([point_contact([-1, 0], [-1, 0], "hard", 0.3),
    ...                        point_contact([1, 0.2], [1, 0], "hard", 0.3)])
    >>> a.verdict.value, a.force_direction_closure, a.contact_forces.shape
    ('closure', True, (2, 2))
    """
    verdict, rank, margin, explanation = _analysis(check_grasp(contacts), cone, tol, reference,
                                                   length_scale)
    return Analysis(verdict, rank, margin, partial(_given, explanation))


def _given(explanation: _Explanation) -> _Explanation:
    return explanation


def _analysis(contacts: list[Contact], cone: str | Cone, tol: float,
              reference: ArrayLike | None, length_scale: float | None,
              ) -> tuple[Verdict, int, float | None, _Explanation]:
    """:func:`analyze` by the reference path: the verdict, rank, margin and explanation."""
    vc, ws, label, used, use, half = _decision(contacts, cone, tol, reference, length_scale)
    margin = vc.margin
    ref, scale = ws.reference, ws.length_scale
    if reference is not None or length_scale is not None:  # the margin in the user's frame
        ref, scale = frame(contacts, reference, length_scale)
        if margin is not None:
            own = generating_wrenches(used, use, reference, length_scale, half_space=half)
            margin = vector_closure(own.wrenches, tol, own.two_sided).margin
    forces = None
    twist = motion = None
    if vc.verdict is Verdict.CLOSURE:
        fd = tc = True
        d = contacts[0].dim
        forces = np.zeros((len(contacts), d))
        assert vc.weights is not None  # a closure carries its weights
        np.add.at(forces, ws.contact_index, (ws.wrenches[:d] * vc.weights).T)
    else:
        fd = force_direction_closure(ws.wrenches, tol)
        # closure <=> both; so with force-direction closure, torque closure failed
        tc = not fd and torque_closure(ws.wrenches)
        dual, both_ways = vc.twist, vc.repelling <= tol
        if vc.verdict is Verdict.NONE and not fd:
            dual, both_ways = _translation(ws.wrenches, tol) or (dual, both_ways)
        if dual is not None:
            motion = _motion(dual, contacts, both_ways)
            twist = motion.twist
    return vc.verdict, vc.rank, margin, _Explanation(
        vc.sigma_ratio, fd, tc, forces, twist, motion, vc.reason.replace("vectors", "wrenches"),
        label, ref, scale)


def _explained(contacts: list[Contact], cone: str | Cone, tol: float,
               verdict: Verdict) -> _Explanation:
    """The explanation of a verdict the compiled kernel gave, by the reference path. Both
    are certified, so they differ only within the tolerance band (one says ``marginal``);
    the reason then says so."""
    found, _, _, explanation = _analysis(contacts, cone, tol, None, None)
    if found is verdict:
        return explanation
    note = (f"{explanation.reason} (the explanation's reference path finds this grasp "
            f"{found.value}, within the tolerance band of the boundary)")
    return _Explanation(**{**explanation.__dict__, "reason": note})


#: The compiled Theorem 1 module, once :func:`_ready_kernel` has found it may be used.
_KERNEL: list = []


def _ready_kernel():
    """The compiled Theorem 1 module when its serial kernel may run (compiled, or to be
    compiled now: :func:`forceclosure.kernels.use_compiled`), else None."""
    from ..kernels import theorem1, use_compiled

    if not use_compiled(theorem1.closure_serial):
        return None
    _KERNEL[:] = [theorem1]
    return theorem1


def _compiled(contacts: list[Contact], cone: str | Cone, tol: float,
              ) -> tuple[Verdict, int, float | None] | None:
    """Theorem 1 for a grasp of point contacts by the compiled kernel, on this thread:
    ``(verdict, rank, margin)``, or None where the kernel defers (or cannot take the grasp:
    edge, face or vertex contacts, friction above :data:`FRICTION_CAP`, coordinates
    beyond ``2**±64``; or is not compiled yet, :func:`forceclosure.kernels.use_compiled`)
    and the reference path decides."""
    tol = check_tolerance(tol)
    fixed = fixed_cone(cone)
    for c in contacts:
        if len(c.points) != 1 or len(c.normals) != 1 or (c.frictional and c.mu > FRICTION_CAP):
            return None
    P = np.concatenate([c.points for c in contacts])  # fresh, writeable: the kernels' type
    big = max(-P.min(), P.max())
    if big != 0 and not 2.0**-64 <= big <= 2.0**64:
        return None
    if any(c.torsion is not None for c in contacts):
        _check_torsion(contacts)
    kernel = _KERNEL[0] if _KERNEL else _ready_kernel()
    if kernel is None:
        return None  # a first answer now, by the reference path, not after compiling
    N = np.concatenate([c.normals for c in contacts])
    exact = fixed is None
    edges, fit = (8, 0) if fixed is None else (fixed.edges, int(fixed.fit == "circumscribed"))
    friction = np.array([[c.mu for c in contacts],
                         [math.nan if c.torsion is None else c.torsion for c in contacts]])
    model = model_codes([c.model for c in contacts])
    codes, ranks, margins = np.empty(1, np.int8), np.empty(1, np.int64), np.empty(1)
    kernel.closure_serial(P[None], N[None], friction[:1], friction[1:], model, edges, fit, exact,
                          float(tol),
                          kernel.columns_per_grasp(len(contacts), P.shape[1],
                                                   256 if exact else edges),
                          codes, ranks, margins, np.empty((1, 3 if P.shape[1] == 2 else 6)))
    code, margin = int(codes[0]), float(margins[0])
    if code == kernel.DEFER:
        return None
    return (Verdict.of_code(code), int(ranks[0]), None if math.isnan(margin) else margin)


