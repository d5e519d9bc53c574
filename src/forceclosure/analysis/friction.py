"""Least friction: the smallest friction coefficient, the same at every finger, that
makes a grasp force-closure.

Frictionless contacts are taken as hard fingers. Planar two-finger grasps and
spatial soft pairs (exact cones) are in closed form
(:mod:`forceclosure.analysis.two_finger`); others bisect on the cone angle, a monotone
question: :func:`least_friction_reference` over full analyses, or
:func:`least_friction_batch` inside the compiled kernel, many grasps at once.
:func:`least_friction` takes the compiled path for point contacts.

Examples
--------
Two fingers inside a ring push apart (the object's outward normals face each other):
Corollary 3 in its spreading sense, ``mu* = tan`` of the angle of ``PQ``, ``0.2 / 2``.

>>> from forceclosure import point_contact
>>> apart = [point_contact([-1, 0], [1, 0], "hard"), point_contact([1, 0.2], [-1, 0], "hard")]
>>> round(least_friction(apart), 6)
0.1
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..contacts import Cone, Contact, check_grasp, model_codes
from .batch_analysis import (
    Engine,
    check_engine,
    cone_args,
    extreme_grasps,
    kernel_inputs,
    validate_grasps,
)
from .closure import TOLERANCE, Verdict, check_rtol, check_tolerance, decide
from .two_finger import MU_MAX, pair_least_friction, two_finger_closure

__all__ = ["MU_MAX", "least_friction", "least_friction_batch", "least_friction_reference"]

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

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, §4.1, Corollary 3
       (two opposing fingers, in closed form)
    .. [2] R. M. Murray, Z. Li and S. S. Sastry, *A Mathematical Introduction to Robotic
       Manipulation*, CRC Press, 1994, ch. 5

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
    from ..kernels import pairs, theorem1, use_compiled

    if all(len(c.points) == 1 and len(c.normals) == 1 for c in contacts) and use_compiled(
            pairs.pair_verdict_kernel, theorem1.least_friction_kernel):
        # point contacts: one compiled bisection (closed forms for pairs), the reference
        # below only where the kernel defers (or before the kernels are compiled)
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


def least_friction_batch(points: ArrayLike, normals: ArrayLike, *,
                         model: str | Sequence[str] = "hard", torsion: ArrayLike | None = None,
                         cone: str | Cone = "exact", tol: float = TOLERANCE, rtol: float = 1e-6,
                         engine: Engine = "compiled") -> NDArray[np.float64]:
    """The least friction coefficient, equal at all fingers, closing each grasp.

    The batch form of :func:`forceclosure.analysis.quality.least_friction`: frictionless
    contacts count as hard fingers, 0 means closed without friction, ``inf``
    that no friction up to :data:`forceclosure.analysis.quality.MU_MAX` closes the
    grasp. Compiled, it is one parallel pass over the grasps: each grasp's
    bisection on the cone half-angle runs inside the kernel. Planar pairs
    and spatial soft pairs with the paper's uncoupled torque are exact in
    closed form (:mod:`forceclosure.analysis.two_finger`), as in the reference.

    Examples
    --------
    Two fingers on opposite sides, one 0.2 higher than the other: ``tan`` of
    the angle of ``PQ``, 0.2 / 2, in the plane (Corollary 3 in closed form)
    and for soft fingers in space (an 8-edge pyramid has an edge along the
    offset, so it agrees with the circular cone):

    >>> import numpy as np
    >>> P = np.array([[[-1, 0, 0], [1, 0.2, 0]]])
    >>> N = np.array([[[-1, 0, 0], [1, 0, 0]]])
    >>> round(float(least_friction_batch(P[..., :2], N[..., :2])[0]), 6)
    0.1
    >>> least_friction_batch(P, N, model="soft", cone=Cone(8)).round(6).tolist()
    [0.1]
    """
    check_engine(engine)
    tol = check_tolerance(tol)
    rtol = check_rtol(rtol)
    grasps = validate_grasps(points, normals, 0.0, model, torsion)
    exact, edges, fit = cone_args(cone)
    n, k, d = grasps.points.shape
    out = np.empty(n)
    soft = [i for i, m in enumerate(grasps.models) if m == "soft"]
    closed_form = k == 2 and (d == 2 or (len(soft) == 2 and exact)) and bool(
        np.all(np.isnan(grasps.torsion[:, soft])))
    if engine == "reference":
        todo = np.arange(n)
    elif closed_form:  # Corollary 3, and its exact spatial form for soft pairs
        P, N_ = grasps.points, grasps.normals
        least = pair_least_friction(P[:, 0], N_[:, 0], P[:, 1], N_[:, 1])
        return np.where(least > MU_MAX, np.inf, least)
    else:
        from ..kernels import announce_compiling, kernel_array, pool_for
        from ..kernels import theorem1 as kernel

        kinds = model_codes(grasps.models)
        maxm = kernel.columns_per_grasp(k, d, 256 if exact else edges)
        deferred = np.zeros(n, dtype=np.bool_)
        extreme = extreme_grasps(grasps)
        P = kernel_inputs(grasps, slice(0, n), extreme)[0]
        announce_compiling(kernel.least_friction_kernel)
        with pool_for(n):
            kernel.least_friction_kernel(P, kernel_array(grasps.normals),
                                         kernel_array(grasps.torsion), kinds, edges, fit,
                                         exact, float(tol), maxm, MU_MAX, float(rtol), out,
                                         deferred)
        todo = np.flatnonzero(deferred | extreme)
    for g in todo:
        out[g] = least_friction_reference(grasps.contacts(g), cone=cone, tol=tol, rtol=rtol)
    return out
