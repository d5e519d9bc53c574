"""Grasp-matrix metrics: smallest singular value, isotropy, volume of the wrench hull.

The quality measures of GraspIt! and Dex-Net beside the Ferrari–Canny
epsilon, for ``N`` grasps of ``k`` point contacts at once, in **the frame of
the library's epsilon** (:func:`forceclosure.analysis.batch.epsilon_batch`): torques
are taken about the contacts' centroid and divided by their largest
distance from it, the length scale ``L`` (1 when the contacts coincide), so
forces and torques are in the same units and every metric is
dimensionless and unchanged by moving, rotating or scaling the grasp.

* **Grasp matrix** ``G`` (``D × m``, ``D`` = 3 planar or 6 spatial): the
  map from the contact forces, in each contact's frame, to the wrench on
  the object. A contact at ``p`` with outward normal ``n`` gives the columns
  ``(e, (p - c) × e / L)`` for ``e = -n`` (frictionless), ``e`` in ``(t1, t2,
  -n)`` (hard finger, spatial; ``(t, -n)`` planar) and a soft finger in space
  adds ``(0, n)``: a torsional moment of ``L`` per unit, the paper's pure
  torque as in :func:`forceclosure.generating_wrenches` (a planar soft
  finger's torsion acts out of the plane: it has the hard finger's columns).
* **Smallest singular value** ``σ_min(G)`` (Li & Sastry): how far the grasp
  is from losing a wrench direction; 0 when ``G`` is rank-deficient (two
  hard fingers in space). **Isotropy** ``σ_min / σ_max``: 1 when every
  direction of wrench is equally easy to apply.
* **Volume of the wrench hull** (GraspIt!'s volume quality): the volume of
  the convex hull of the generating wrenches (unit normal force, ``edges``-edge
  inscribed pyramids oriented by the grasp,
  :func:`forceclosure.geometry.cones.fill_frame`), the same hull whose
  inscribed ball is the L1 epsilon. It is **0 when the generators do not span the wrench space**
  (their hull is flat, e.g. a hard pair in space), as a flat body has no
  volume.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..contacts import Cone, primitive_wrenches, tangent_basis
from ..geometry.cones import fill_frame

__all__ = ["GraspMetrics", "grasp_matrix", "grasp_metrics"]


@dataclass(frozen=True, eq=False)
class GraspMetrics:
    """Metrics of ``N`` grasps (:func:`grasp_metrics`).

    Attributes
    ----------
    sigma_min, sigma_max : (N,) arrays
        Smallest and largest singular values of the grasp matrix.
    isotropy : (N,) array
        ``sigma_min / sigma_max`` (0 when both are 0).
    volume : (N,) array
        Volume of the convex hull of the generating wrenches; 0 when they
        do not span the wrench space.
    reference : (N, d) array, length_scale : (N,) array
        The torque frame: the contacts' centroid and largest distance from it.
    """

    sigma_min: NDArray[np.float64]
    sigma_max: NDArray[np.float64]
    isotropy: NDArray[np.float64]
    volume: NDArray[np.float64]
    reference: NDArray[np.float64]
    length_scale: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.sigma_min)


def _frame(P: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Each grasp's centroid and largest distance from it (1 when the points coincide)."""
    ref = P.mean(axis=1)
    scale = np.max(np.linalg.norm(P - ref[:, None], axis=2), axis=1)
    big = np.max(np.abs(P), axis=(1, 2))
    return ref, np.where(scale <= 1e-12 * np.maximum(1.0, big), 1.0, scale)


def _columns(P: NDArray, N: NDArray, model: str, ref: NDArray, scale: NDArray) -> NDArray:
    """Grasp-matrix columns ``(n, D, c)`` of one contact slot."""
    d = P.shape[1]
    if d == 2:
        t = np.stack([-N[:, 1], N[:, 0]], axis=-1)
        forces = [-N] if model == "frictionless" else [t, -N]
    else:
        t1, t2 = tangent_basis(N)
        forces = [-N] if model == "frictionless" else [t1, t2, -N]
    r = (P - ref) / scale[:, None]
    cols = []
    for f in forces:
        tau = (r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])[:, None] if d == 2 else np.cross(r, f)
        cols.append(np.concatenate([f, tau], axis=1))
    if model == "soft" and d == 3:
        cols.append(np.concatenate([np.zeros_like(N), N], axis=1))
    return np.stack(cols, axis=2)


def grasp_matrix(points: ArrayLike, normals: ArrayLike,
                 model: str | Sequence[str] = "hard") -> NDArray[np.float64]:
    """The grasp matrices ``(N, D, m)`` of ``N`` grasps of ``k`` contacts (``(N, k, d)``).

    Columns per contact as in the module's docstring, contact after contact;
    torques about the contacts' centroid per their largest distance from it.

    References
    ----------
    .. [1] R. M. Murray, Z. Li and S. S. Sastry, *A Mathematical Introduction to Robotic
       Manipulation*, CRC Press, 1994, ch. 5
    .. [2] Z. Li and S. S. Sastry, "Task-oriented optimal grasping by multifingered
       robot hands", *IEEE J. Robotics and Automation* 4(1):32-44, 1988

    Examples
    --------
    Two hard fingers pinching the unit cube: six columns, rank 5 (nothing
    resists rotation about the line through the contacts):

    >>> P = [[[-0.5, 0, 0], [0.5, 0, 0]]]
    >>> N = [[[-1.0, 0, 0], [1, 0, 0]]]
    >>> G = grasp_matrix(P, N)
    >>> G.shape, int(np.linalg.matrix_rank(G[0]))
    ((1, 6, 6), 5)
    """
    from .batch_analysis import validate_grasps

    grasps = validate_grasps(points, normals, 0.0, model, None)
    P, N = grasps.points, grasps.normals
    ref, scale = _frame(P)
    if len(P) == 0:
        return np.zeros((0, 3 if P.shape[2] == 2 else 6, 0))
    return np.concatenate([_columns(P[:, i], N[:, i], m, ref, scale)
                           for i, m in enumerate(grasps.models)], axis=2)


def _volume(points: NDArray[np.float64]) -> float:
    """Volume of the convex hull of ``points`` (``(m, D)``); 0 when they do not span ``R^D``."""
    from scipy.spatial import ConvexHull, QhullError

    D = points.shape[1]
    centred = points - points.mean(axis=0)
    if len(points) <= D or np.linalg.matrix_rank(centred, tol=1e-10) < D:
        return 0.0
    try:
        return float(ConvexHull(points).volume)
    except (QhullError, ValueError):
        return 0.0


def grasp_metrics(points: ArrayLike, normals: ArrayLike, *, mu: ArrayLike = 0.0,
                  model: str | Sequence[str] = "hard", torsion: ArrayLike | None = None,
                  edges: int = 8) -> GraspMetrics:
    """Smallest singular value, isotropy and wrench-hull volume of ``N`` grasps.

    Parameters
    ----------
    points, normals : (N, k, d) arrays
        Contact points and outward normals (normalised here).
    mu, torsion : arrays broadcastable to (N, k)
        Friction and torsional coefficients, as in
        :func:`forceclosure.analysis.batch.analyze_batch`; only the volume uses them.
    model : str or sequence of k str
        Contact model of every contact, or of each contact slot.
    edges : int
        Edges of the inscribed pyramids of the volume's generators.

    The singular values take one batched SVD; the volume one Qhull call per
    grasp (about a millisecond for a spatial pair).

    References
    ----------
    .. [1] Z. Li and S. S. Sastry, "Task-oriented optimal grasping by multifingered
       robot hands", *IEEE J. Robotics and Automation* 4(1):32-44, 1988
    .. [2] J. K. Salisbury and J. J. Craig, "Articulated hands: force control and
       kinematic issues", *Int. J. Robotics Research* 1(1):4-17, 1982
    .. [3] M. A. Roa and R. Suárez, "Grasp quality measures: review and performance",
       *Autonomous Robots* 38(1):65-88, 2015

    Examples
    --------
    Two soft fingers pinching the unit cube head-on: ``G Gᵀ = 2 I`` (forces
    from both, torques from the lever arms and the two torsions), so every
    singular value is √2:

    >>> m = grasp_metrics([[[-0.5, 0, 0], [0.5, 0, 0]]], [[[-1.0, 0, 0], [1, 0, 0]]],
    ...                   mu=0.5, model="soft")
    >>> m.sigma_min.round(6).tolist(), m.isotropy.round(6).tolist(), bool(m.volume[0] > 0)
    ([1.414214], [1.0], True)
    """
    from .batch_analysis import validate_grasps

    grasps = validate_grasps(points, normals, mu, model, torsion)
    cone = Cone(edges, "inscribed")
    P, N = grasps.points, grasps.normals
    n = len(P)
    ref, scale = _frame(P)
    G = grasp_matrix(P, N, grasps.models)
    if n:
        sv = np.linalg.svd(G, compute_uv=False).astype(float, copy=False)
        smin = sv[:, -1] if G.shape[2] >= G.shape[1] else np.zeros(n)
        smax = sv[:, 0]
    else:
        smin = smax = np.zeros(0)
    with np.errstate(invalid="ignore", divide="ignore"):
        iso = np.where(smax > 0, smin / np.where(smax > 0, smax, 1.0), 0.0)
    volume = np.zeros(n)
    if n:
        tangents: list[tuple[NDArray[np.float64], NDArray[np.float64]] | None]
        tangents = [None] * P.shape[1]
        if P.shape[2] == 3:  # the pyramids oriented by each grasp, as epsilon's
            frames = np.empty((n, P.shape[1], 2, 3))
            for g in range(n):
                fill_frame(P[g], N[g], frames[g])
            tangents = [(frames[:, i, 0], frames[:, i, 1]) for i in range(P.shape[1])]
        W = np.concatenate([
            primitive_wrenches(P[:, i], N[:, i], m, grasps.mu[:, i], grasps.torsion[:, i],
                               ref, scale, cone, tangents[i])
            for i, m in enumerate(grasps.models)], axis=2)
        for g in range(n):
            volume[g] = _volume(W[g].T)
    return GraspMetrics(smin, smax, iso, volume, ref, scale)
