"""Grasp quality beyond the verdict: Ferrari–Canny epsilon and least friction.

Both are computed for grasps that are already known to be force-closure
(epsilon is 0 otherwise). Quality metrics, unlike verdicts, depend on where
torques are measured and how they are scaled: each result states its torque
reference point and length scale.

* **Epsilon** (Ferrari & Canny 1992): the radius of the largest ball about
  the origin inside the convex hull of the grasp's wrenches, with each
  finger's normal force at most 1 — in total (``L1``: the hull of all
  generators) or each (``Linf``: the Minkowski sum of the fingers' hulls with
  the origin). Torques are divided by the length scale, so epsilon is
  dimensionless. Spatial cones are the inscribed pyramid, so the value is a
  lower bound for circular cones. Friction above
  :data:`forceclosure.closure.FRICTION_CAP` is measured as that much (a lower
  bound too).
* **Least friction**: the smallest friction coefficient, the same at every
  finger, for which the grasp is force-closure (frictionless contacts taken
  as hard fingers). Planar two-finger grasps and spatial soft pairs (exact
  cones) are in closed form (:mod:`forceclosure.two_finger`); others bisect
  on the cone angle, a monotone question.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import ConvexHull, QhullError

from .closure import (
    FRICTION_CAP,
    TOLERANCE,
    Verdict,
    check_rtol,
    check_tolerance,
    decide,
)
from .contacts import Cone, Contact, check_grasp, generating_wrenches
from .errors import InputError
from .two_finger import two_finger_closure

#: Largest friction coefficient tried; beyond it cones are numerically half-spaces.
MU_MAX = 1e4

#: Largest number of points whose hull the L-infinity epsilon will build.
LINF_MAX_POINTS = 200_000


@dataclass(frozen=True)
class Epsilon:
    """Ferrari–Canny epsilon and the frame it was measured in."""

    value: float
    norm: str
    reference: tuple[float, ...]
    length_scale: float
    cone: str


def _hull_radius(points: np.ndarray) -> float:
    try:
        hull = ConvexHull(points)
    except (QhullError, ValueError):
        return 0.0
    return max(0.0, float(np.min(-hull.equations[:, -1])))


def epsilon(contacts: Sequence[Contact], norm: Literal["L1", "Linf"] = "L1", *, edges: int = 8,
            reference: ArrayLike | None = None, length_scale: float | None = None,
            tol: float = TOLERANCE) -> Epsilon:
    """Ferrari–Canny epsilon quality of a force-closure grasp.

    Parameters
    ----------
    contacts : sequence of Contact
    norm : {"L1", "Linf"}
        Bound on the sum of the fingers' normal forces, or on each.
    edges : int
        Edges of the inscribed pyramid standing in for spatial cones.
    reference, length_scale :
        Torque frame (default: the contacts' centroid and largest distance
        from it).

    Returns
    -------
    Epsilon
        ``value`` is 0 for a grasp that is not force-closure.

    Examples
    --------
    Two fingers pinching head-on with friction 0.5: the hull of the four
    wrenches is a tetrahedron whose nearest face is 1/3 from the origin:

    >>> from forceclosure import point_contact
    >>> grasp = [point_contact([-1, 0], [-1, 0], "hard", 0.5),
    ...          point_contact([1, 0], [1, 0], "hard", 0.5)]
    >>> round(epsilon(grasp).value, 6)
    0.333333
    """
    contacts = check_grasp(contacts)
    if norm not in ("L1", "Linf"):
        raise InputError(f"norm must be 'L1' or 'Linf', got {norm!r}")
    cone = Cone(edges, "inscribed")
    # friction above the cap is measured as the cap: a lower bound, as epsilon grows with it
    contacts = [Contact(c.points, c.normals, c.model, FRICTION_CAP, c.torsion)
                if c.mu > FRICTION_CAP else c for c in contacts]
    ws = generating_wrenches(contacts, cone, reference, length_scale)
    label = "exact planar cones" if contacts[0].dim == 2 else f"{cone}s"
    result = Epsilon(0.0, norm, tuple(ws.reference.tolist()), ws.length_scale, label)
    # closed with exact cones and with the pyramid measured (verdicts in the grasp's own frame)
    if decide(contacts, "exact", tol, reference, length_scale)[0].verdict is not Verdict.CLOSURE \
            or decide(contacts, cone, tol)[0].verdict is not Verdict.CLOSURE:
        return result
    W = ws.wrenches
    if norm == "L1":
        value = _hull_radius(W.T)
    else:
        total = math.prod(int(np.sum(ws.contact_index == i)) + 1 for i in range(len(contacts)))
        if total > LINF_MAX_POINTS:
            raise InputError(f"Linf epsilon would need the hull of {total} points (more than "
                             f"{LINF_MAX_POINTS}); use fewer cone edges or the L1 norm")
        points = np.zeros((1, W.shape[0]))
        for i in range(len(contacts)):
            own = np.vstack([np.zeros(W.shape[0]), W[:, ws.contact_index == i].T])
            points = (points[:, None, :] + own[None, :, :]).reshape(-1, W.shape[0])
            if len(points) > 4 * W.shape[0] and i < len(contacts) - 1:
                with contextlib.suppress(QhullError, ValueError):
                    points = points[ConvexHull(points).vertices]
        value = _hull_radius(points)
    return Epsilon(value, norm, result.reference, result.length_scale, label)


def _closes(contacts: list[Contact], mu: float, cone: str | Cone, tol: float) -> bool:
    grasp = [c.with_friction(mu) for c in contacts]
    return decide(grasp, cone, tol)[0].verdict is Verdict.CLOSURE


def least_friction(contacts: Sequence[Contact], *, cone: str | Cone = "exact",
                   tol: float = TOLERANCE, rtol: float = 1e-6) -> float:
    """The least friction coefficient, equal at all fingers, that closes the grasp.

    Parameters
    ----------
    contacts : sequence of Contact
        Their own ``mu`` is ignored; frictionless contacts count as hard
        fingers, soft fingers stay soft.
    cone : "exact" or Cone
        As in :func:`forceclosure.analyze`.
    rtol : float
        Relative precision of the bisection on the cone half-angle.

    Returns
    -------
    float
        0 when the grasp is force-closure without friction; ``inf`` when no
        friction up to :data:`MU_MAX` closes it. The grasp is force-closure for any larger value.

    Examples
    --------
    >>> from forceclosure import point_contact
    >>> grasp = [point_contact([-1, 0], [-1, 0], "hard"),
    ...          point_contact([1, 0.2], [1, 0], "hard")]
    >>> round(least_friction(grasp), 6)   # tan of the angle of PQ: 0.2 / 2
    0.1
    """
    contacts = check_grasp(contacts)
    tol = check_tolerance(tol)
    rtol = check_rtol(rtol)
    from .kernels import pairs, theorem1, use_compiled

    if all(len(c.points) == 1 and len(c.normals) == 1 for c in contacts) and use_compiled(
            pairs.pair_kernel, theorem1.least_friction_kernel):
        # point contacts: one compiled bisection (closed forms for pairs), the reference
        # below only where the kernel defers (or before the kernels are compiled)
        from .batch import least_friction_batch

        models = ["hard" if c.model == "frictionless" else c.model for c in contacts]
        torsion = [[np.nan if c.torsion is None else c.torsion for c in contacts]]
        return float(least_friction_batch(
            [[c.point for c in contacts]], [[c.normal for c in contacts]], model=models,
            torsion=torsion, cone=cone, tol=tol, rtol=rtol)[0])
    return least_friction_reference(contacts, cone=cone, tol=tol, rtol=rtol)


def least_friction_reference(contacts: Sequence[Contact], *, cone: str | Cone = "exact",
                             tol: float = TOLERANCE, rtol: float = 1e-6) -> float:
    """:func:`least_friction` by bisection over full analyses (:func:`forceclosure.analyze`'s
    path): for any contacts, and the reference the compiled kernel is checked against.

    Examples
    --------
    >>> from forceclosure import point_contact
    >>> grasp = [point_contact([-1, 0], [-1, 0], "hard"),
    ...          point_contact([1, 0.2], [1, 0], "hard")]
    >>> round(least_friction_reference(grasp), 6)
    0.1
    """
    contacts = check_grasp(contacts)
    tol = check_tolerance(tol)
    rtol = check_rtol(rtol)
    pair = (len(contacts) == 2 and all(len(c.points) == 1 and len(c.normals) == 1
                                       for c in contacts)
            and all(c.model != "soft" or c.torsion is None for c in contacts))
    if pair and (contacts[0].dim == 2
                 or (cone == "exact" and all(c.model == "soft" for c in contacts))):
        # Corollary 3 in the plane, and its exact spatial form for soft pairs, in closed form
        a, b = contacts
        least = float(two_finger_closure(a.point, a.normal, b.point, b.normal, 1.0,
                                         engine="reference").least_friction)
        return math.inf if least > MU_MAX else least
    if _closes(list(contacts), 0.0, cone, tol):
        return 0.0
    hi = math.atan(MU_MAX)
    if not _closes(list(contacts), MU_MAX, cone, tol):
        return math.inf
    lo = 0.0
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if _closes(list(contacts), math.tan(mid), cone, tol):
            hi = mid
        else:
            lo = mid
    return math.tan(hi)
