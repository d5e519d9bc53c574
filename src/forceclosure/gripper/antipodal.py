"""Antipodal jaw poses sampled on a mesh.

:func:`sample_antipodal` draws surface points (uniform over the area), a
closing direction inside each point's friction cone around the inward
normal (uniform over the cone's spherical cap), and closes a parallel-jaw
gripper along that line: jaw 1 just outside the point, jaw 2 ``width_max``
away. Both jaws' rays go in one batched query
(:func:`forceclosure.gripper.jaw.jaw_contacts`); each candidate's contact pair is what
the jaws meet first.
By construction the line of every pair lies inside the first contact's
friction cone; whether the pair is force-closure is for the labels
(:mod:`forceclosure.gripper.labels`). Deterministic under a seed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..synthesis.spatial.patches import uniform_in_triangles
from .jaw import TOO_WIDE, JawPose, jaw_contacts, surface_mesh

__all__ = ["AntipodalSamples", "draw_lines", "sample_antipodal"]

#: Rounds of sampling before giving up on reaching ``count`` candidates.
ROUNDS = 8


@dataclass(frozen=True, eq=False)
class AntipodalSamples:
    """``N`` sampled jaw poses and the contact pairs they make.

    Attributes
    ----------
    center, closing_axis, approach_axis : (N, 3) arrays
    width : (N,) array
        The distance between the two contacts (the jaws' opening at the grasp).
    points, normals : (N, 2, 3) arrays
        The contacts of jaw 1 and jaw 2; outward unit normals.
    triangles : (N, 2) int array
        The mesh triangles the contacts lie on.
    attempts : int
        Surface points drawn.
    rejected : dict
        How many drawn points made no candidate, by reason.
    """

    center: NDArray[np.float64]
    closing_axis: NDArray[np.float64]
    approach_axis: NDArray[np.float64]
    width: NDArray[np.float64]
    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    triangles: NDArray[np.int64]
    attempts: int
    rejected: dict[str, int] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.width)

    def pose(self, i: int) -> JawPose:
        """Candidate ``i`` as a :class:`~forceclosure.gripper.jaw.JawPose`."""
        return JawPose(self.center[i], self.closing_axis[i], self.approach_axis[i],
                       float(self.width[i]))


def _perpendicular(v: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
    """Two unit vectors completing each row of ``v`` (unit, ``(n, 3)``) to a right-handed
    orthonormal frame."""
    axis = np.eye(3)[np.argmin(np.abs(v), axis=1)]
    e1 = axis - np.einsum("ij,ij->i", axis, v)[:, None] * v
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    return e1, np.cross(v, e1)


def _draw(V, T, normals, mu: float, m: int, rng: np.random.Generator):
    """``m`` surface points, their outward normals and triangles, and closing directions
    uniform over the cap of half-angle ``atan(mu)`` around the inward normal (strictly
    inside it), and an approach angle each."""
    points, tri = uniform_in_triangles(V[T[:, 0]], V[T[:, 1]], V[T[:, 2]], m, rng)
    n = normals[tri]
    cos_alpha = 1.0 / np.sqrt(1.0 + mu * mu)
    cos_t = 1.0 - rng.random(m) * (1.0 - cos_alpha)  # in (cos alpha, 1]
    sin_t = np.sqrt(np.maximum(0.0, 1.0 - cos_t**2))
    phi = rng.random(m) * 2 * np.pi
    e1, e2 = _perpendicular(-n)
    d = (cos_t[:, None] * -n + sin_t[:, None] * (np.cos(phi)[:, None] * e1
                                                 + np.sin(phi)[:, None] * e2))
    d /= np.linalg.norm(d, axis=1)[:, None]
    return points, d, rng.random(m) * 2 * np.pi


def draw_lines(mesh, mu: float, m: int, rng: np.random.Generator, tilt: float = 1.0
               ) -> tuple[NDArray, NDArray, NDArray]:
    """``m`` closing lines on a mesh (outward faces): points uniform over the surface, a
    direction each uniform over the cap of half-angle ``tilt · atan(mu)`` around the
    inward normal (``tilt`` 0: the inward normal itself), and an approach axis each
    perpendicular to it (uniform angle)."""
    cap = float(np.tan(tilt * np.arctan(mu)))
    p, d, angle = _draw(mesh.vertices, mesh.faces, mesh.face_normals, cap, m, rng)
    e1, e2 = _perpendicular(d)
    return p, d, np.cos(angle)[:, None] * e1 + np.sin(angle)[:, None] * e2


def sample_antipodal(obj: Any, mu: float, count: int, seed: int = 0,
                     width_max: float = np.inf) -> AntipodalSamples:
    """Sample ``count`` antipodal jaw poses on a mesh (fewer when too few points make one).

    Parameters
    ----------
    obj : file, bundled name, trimesh.Trimesh or Polyhedron
    mu : float
        Friction coefficient of the cone the closing directions are drawn in.
    count : int
        Candidates wanted; points are drawn in up to :data:`ROUNDS` rounds.
    seed : int
        The same seed gives the same candidates.
    width_max : float
        The gripper's widest opening: a line along which the object is wider
        is no candidate (its jaw 2 starts inside the object; counted under
        that reason in ``rejected``, as are rays entering an open mesh
        through a hole).

    References
    ----------
    .. [1] J. Mahler et al., "Dex-Net 2.0: Deep learning to plan robust grasps with
       synthetic point clouds and analytic grasp metrics", *Robotics: Science and
       Systems*, 2017
    .. [2] R. M. Murray, Z. Li and S. S. Sastry, *A Mathematical Introduction to Robotic
       Manipulation*, CRC Press, 1994, ch. 5

    Examples
    --------
    >>> s = sample_antipodal("cube", mu=0.3, count=50, seed=1, width_max=3.0)
    >>> len(s), bool(np.allclose(np.abs(s.points).max(axis=2), 1.0))
    (50, True)
    """
    try:
        mu = float(mu)
        width_max = float(width_max)
    except (TypeError, ValueError, OverflowError):
        raise InputError("mu and width_max must be numbers") from None
    if not np.isfinite(mu) or mu <= 0:
        raise InputError(f"mu must be finite and positive for antipodal sampling, got {mu}")
    if not width_max > 0:
        raise InputError(f"width_max must be positive, got {width_max}")
    if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 0:
        raise InputError(f"count must be a whole number >= 0, got {count!r}")
    poly, mesh = surface_mesh(obj)
    V, T, face_normals = mesh.vertices, mesh.faces, mesh.face_normals
    size = poly.size
    reach = min(width_max, 2.0 * size)  # nothing lies farther apart than the size
    rng = np.random.default_rng(seed)
    parts: list[tuple] = []
    found, attempts = 0, 0
    rejected: dict[str, int] = {}
    for _ in range(ROUNDS):
        if found >= count:
            break
        rate = found / attempts if attempts else 1.0
        m = int(np.ceil((count - found) / max(rate, 0.02) * 1.1)) + 8
        p, d, angle = _draw(V, T, face_normals, mu, m, rng)
        attempts += m
        centers = p + 0.5 * reach * d
        pts, nrm, tris, reasons = jaw_contacts(mesh, size, centers, d, np.full(m, reach))
        width = np.linalg.norm(pts[:, 1] - pts[:, 0], axis=1)
        reasons[(reasons == None) & (width > width_max)] = TOO_WIDE  # noqa: E711
        ok = np.flatnonzero(reasons == None)[: count - found]  # noqa: E711
        for r in reasons[reasons != None]:  # noqa: E711
            rejected[r] = rejected.get(r, 0) + 1
        found += len(ok)
        e1, e2 = _perpendicular(d[ok])
        approach = np.cos(angle[ok])[:, None] * e1 + np.sin(angle[ok])[:, None] * e2
        parts.append((pts[ok], nrm[ok], tris[ok], d[ok], approach))
    pts, nrm, tris, d, approach = (np.concatenate([q[k] for q in parts]) if parts else
                                   np.zeros((0, 2, 3) if k < 2 else (0, 2) if k == 2 else (0, 3))
                                   for k in range(5))
    center = 0.5 * (pts[:, 0] + pts[:, 1])
    width = np.linalg.norm(pts[:, 1] - pts[:, 0], axis=1)
    return AntipodalSamples(center, d, approach, width, pts, nrm, tris.astype(np.int64),
                            attempts, rejected)
