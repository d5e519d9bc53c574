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
  lower bound for circular cones (and at least their value at friction
  ``mu cos(pi / k)``). Each pyramid is oriented by the grasp itself
  (:func:`forceclosure.geometry.cones.fill_frame`: its first edge towards the
  contacts' centroid, with fallbacks), so epsilon does not change when the
  grasp is turned, moved, scaled or its contacts reordered; ``orientation=
  "axes"`` gives the earlier pyramids, oriented by the coordinate axes, whose
  epsilon changes with the turn (by a factor of 0.53 to 4.94 on 53 sampled
  duck grasps, docs/analysis.md). Friction above
  :data:`forceclosure.analysis.closure.FRICTION_CAP` is measured as that much (a lower
  bound too).
* **Least friction**: the smallest friction coefficient, the same at every
  finger, for which the grasp is force-closure (frictionless contacts taken
  as hard fingers). Planar two-finger grasps and spatial soft pairs (exact
  cones) are in closed form (:mod:`forceclosure.analysis.two_finger`); others bisect
  on the cone angle, a monotone question. It is computed in
  :mod:`forceclosure.analysis.friction`, and its names are here too.
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

from ..contacts import ORIENTATIONS, Cone, Contact, Orientation, check_grasp, generating_wrenches
from ..errors import InputError
from .closure import (
    FRICTION_CAP,
    TOLERANCE,
    Verdict,
    decide,
    vector_closure,
)
from .friction import MU_MAX, least_friction, least_friction_reference

__all__ = ["LINF_MAX_POINTS", "MU_MAX", "Epsilon", "epsilon", "least_friction",
           "least_friction_reference"]

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
            tol: float = TOLERANCE, orientation: Orientation = "grasp") -> Epsilon:
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
    orientation : {"grasp", "axes"}
        Where each pyramid has its first edge: from the grasp itself (default;
        :func:`forceclosure.geometry.cones.fill_frame`), so that the value does
        not change when the grasp is turned, moved, scaled or reordered
        (with ``reference`` and ``length_scale`` moved with it), or from the
        coordinate axes, as before (it changes with the turn).

    Returns
    -------
    Epsilon
        ``value`` is 0 for a grasp that is not force-closure (with exact
        cones, or with the pyramids it is measured on).

    References
    ----------
    .. [1] C. Ferrari and J. Canny, "Planning optimal grasps", *Proc. IEEE ICRA*, 1992,
       pp. 2290-2295
    .. [2] A. T. Miller and P. K. Allen, "GraspIt! A versatile simulator for robotic
       grasping", *IEEE Robotics & Automation Magazine* 11(4):110-122, 2004

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
    if orientation not in ORIENTATIONS:
        raise InputError(f"orientation must be 'grasp' or 'axes', got {orientation!r}")
    cone = Cone(edges, "inscribed")
    # friction above the cap is measured as the cap: a lower bound, as epsilon grows with it
    contacts = [Contact(c.points, c.normals, c.model, FRICTION_CAP, c.torsion)
                if c.mu > FRICTION_CAP else c for c in contacts]
    ws = generating_wrenches(contacts, cone, reference, length_scale, orientation=orientation)
    label = "exact planar cones" if contacts[0].dim == 2 else (
        f"{cone}s" + (" oriented by the grasp" if orientation == "grasp" else ""))
    result = Epsilon(0.0, norm, tuple(ws.reference.tolist()), ws.length_scale, label)
    # closed with exact cones and with the pyramids measured (verdicts in the grasp's own frame)
    if decide(contacts, "exact", tol, reference, length_scale)[0].verdict is not Verdict.CLOSURE:
        return result
    own = ws if reference is None and length_scale is None else generating_wrenches(
        contacts, cone, orientation=orientation)
    if vector_closure(own.wrenches, tol, own.two_sided).verdict is not Verdict.CLOSURE:
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
            options = np.vstack([np.zeros(W.shape[0]), W[:, ws.contact_index == i].T])
            points = (points[:, None, :] + options[None, :, :]).reshape(-1, W.shape[0])
            if len(points) > 4 * W.shape[0] and i < len(contacts) - 1:
                with contextlib.suppress(QhullError, ValueError):
                    points = points[ConvexHull(points).vertices]
        value = _hull_radius(points)
    return Epsilon(value, norm, result.reference, result.length_scale, label)
