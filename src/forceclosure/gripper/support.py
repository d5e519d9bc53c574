"""A table under the object: the support plane the hand must not cross.

:func:`support_plane` rests the object on a table in its most stable pose
(``trimesh.poses.compute_stable_poses``: the faces of its convex hull, the
one whose quasi-static probability of coming to rest is highest) and gives
the table's plane in the object's own frame: the upward unit normal ``n``
and the height ``d`` of the plane along it (the object's lowest point), so
that the table is ``{x : n·x = d}`` and the free side ``n·x ≥ d``.
:func:`crosses_plane` tells which hands cross it: the hand's boxes
(:func:`~forceclosure.gripper.collision.hand_boxes`, opened at each pose
as the collision check opens them) are convex, so a box lies on the free
side exactly when its eight corners do. Jaw poses stay in the object's frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .jaw import ParallelJaw

__all__ = ["SupportPlane", "box_corners", "crosses_plane", "support_plane"]

#: A corner may dip below the plane by this share of the gripper's opening (rounding).
PLANE_RTOL = 1e-9


@dataclass(frozen=True)
class SupportPlane:
    """The table under the object, in its frame: ``normal · x = offset`` (``normal`` unit,
    pointing up, away from the table); ``probability`` is trimesh's of the object coming to
    rest on it (None when the plane is given, not found)."""

    normal: NDArray[np.float64]
    offset: float
    probability: float | None = None

    def __post_init__(self) -> None:
        try:
            n = np.asarray(self.normal, dtype=float).reshape(3)
            offset = float(self.offset)
        except (TypeError, ValueError):
            raise InputError("support plane: normal must be 3 numbers and offset one") from None
        length = float(np.linalg.norm(n))
        if not (np.all(np.isfinite(n)) and np.isfinite(offset) and length > 1e-12):
            raise InputError(f"support plane: normal {n.tolist()} and offset {offset} must be "
                             "finite, the normal nonzero")
        object.__setattr__(self, "normal", n / length)
        object.__setattr__(self, "offset", offset / length)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``normal``, ``offset``, ``probability``."""
        return {"normal": [float(x) for x in self.normal], "offset": float(self.offset),
                "probability": None if self.probability is None else float(self.probability)}


def support_plane(obj: Any) -> SupportPlane:
    """The table the object rests on in its most stable pose, in the object's frame.

    Refused for an open mesh (its centre of mass, which decides the pose, is undefined).

    Examples
    --------
    A 1 × 2 × 3 box rests on one of its largest faces (x = ±0.5):

    >>> import trimesh
    >>> plane = support_plane(trimesh.creation.box(extents=[1, 2, 3]))
    >>> np.abs(plane.normal).round(9).tolist(), plane.offset
    ([1.0, 0.0, 0.0], -0.5)
    """
    import trimesh

    from .jaw import surface_mesh

    poly, mesh = surface_mesh(obj)
    if not mesh.is_watertight:
        raise InputError(f"{poly.name}: a support plane needs a closed mesh (the stable pose "
                         "follows from its centre of mass); this one is open")
    transforms, probabilities = trimesh.poses.compute_stable_poses(mesh)
    if not len(transforms):
        raise InputError(f"{poly.name}: trimesh finds no stable pose to rest it on")
    best = int(np.argmax(probabilities))
    normal = transforms[best][:3, :3].T @ np.array([0.0, 0.0, 1.0])
    offset = float(np.min(mesh.vertices @ normal))
    return SupportPlane(normal, offset, float(probabilities[best]))


def box_corners(gripper: ParallelJaw, center: ArrayLike, closing: ArrayLike,
                approach: ArrayLike, width: ArrayLike, depths: ArrayLike | None = None,
                clearance: float | None = None) -> NDArray[np.float64]:
    """The corners of the hand's boxes at ``N`` poses, ``(N, 8 * boxes, 3)``, in the world:
    the boxes of :func:`~forceclosure.gripper.collision.hand_boxes` opened to each pose's
    width and moved along the approach by its fingertip depth, as
    :func:`~forceclosure.gripper.collision.collides` places them."""
    from .collision import hand_boxes, jaw_frames

    center = np.asarray(center, dtype=float).reshape(-1, 3)
    n = len(center)
    width = np.asarray(width, dtype=float).reshape(n)
    frames = jaw_frames(center, closing, approach) if n else np.zeros((0, 4, 4))
    shift = (np.zeros(n) if depths is None
             else np.asarray(depths, dtype=float).reshape(n) - gripper.depth)
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    local = []
    for name, extents, middle in hand_boxes(gripper, 0.0, clearance):
        side = -1.0 if name == "jaw1" else 1.0 if name == "jaw2" else 0.0
        c = np.repeat(middle[None], n, axis=0)
        c[:, 1] += 0.5 * width * side
        c[:, 0] += shift
        local.append(c[:, None, :] + 0.5 * signs[None] * extents[None, None])
    corners = np.concatenate(local, axis=1) if local else np.zeros((n, 0, 3))
    return np.einsum("nij,nkj->nki", frames[:, :3, :3], corners) + frames[:, None, :3, 3]


def crosses_plane(plane: SupportPlane, gripper: ParallelJaw, center: ArrayLike,
                  closing: ArrayLike, approach: ArrayLike, width: ArrayLike,
                  depths: ArrayLike | None = None, clearance: float | None = None
                  ) -> NDArray[np.bool_]:
    """Which of ``N`` hands cross the support plane: a corner of a box below it (by more
    than :data:`PLANE_RTOL` of the opening).

    Examples
    --------
    The table z = 0 and a hand of opening 3 coming down from above, closing along x: its
    fingertips reach 0.6 below the jaw centre, clear of the table with the centre at height
    1, through it at height 0.5.

    >>> plane = SupportPlane([0, 0, 1], 0.0)
    >>> hand = ParallelJaw(3.0)
    >>> crosses_plane(plane, hand, [[0, 0, 1], [0, 0, 0.5]], [[1, 0, 0]] * 2,
    ...               [[0, 0, -1]] * 2, [2.0, 2.0]).tolist()
    [False, True]
    """
    corners = box_corners(gripper, center, closing, approach, width, depths, clearance)
    height = corners @ plane.normal - plane.offset
    return np.any(height < -PLANE_RTOL * gripper.width_max, axis=1)
