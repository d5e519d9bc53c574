"""Jaw poses a real hand can take: closing lines, then the approach and depth that clear.

:func:`search_poses` draws closing lines through surface points
(:func:`forceclosure.gripper.antipodal.draw_lines`), by default along the
inward normal: a flat pad meets a surface flush where it closes along the
surface's normal, and on a flat face a pad closing at a slant touches with
its rim, far from its centre (``tilt`` > 0 draws directions inside a share
of the friction cone instead, as point-contact samplers do). Along each line
the hand may come from any direction perpendicular to it and hold the line
anywhere along its pads; it searches both, as Dex-Net and GraspNet do:
``approaches`` approach axes turned about the closing axis in even steps
(visited in an order that spreads them: half a turn first, then the
quarters, ...) and ``depths`` fingertip depths spread over the pad (its
middle first). At each the pads close on the object
(:func:`~forceclosure.gripper.pads.pad_contacts`: where the flat pads first
touch, not where a ray from their centres would), and the opened hand is
checked against the object (:func:`~forceclosure.gripper.collision.collides`);
the first pose that clears is kept. A line where none clears keeps its
first pose with contacts, marked colliding; a line where the pads never
hold the object makes no pose (counted by reason).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from .jaw import ParallelJaw, surface_mesh
from .pads import COINCIDE_RTOL, line_candidates, pad_contacts, pad_reach

__all__ = ["APPROACHES", "DEPTHS", "HandPoses", "search_poses", "units_warning"]

#: Approach axes tried per closing line by default.
APPROACHES = 12

#: Fingertip depths tried per approach axis by default.
DEPTHS = 3

#: Reasons a closing line makes no pose.
NOTHING = "the pads close on nothing: no surface under them along this line"
TOO_WIDE = "the object is wider than the opening under the pads"
COINCIDE = (f"the two contacts nearly coincide (closer than {COINCIDE_RTOL:g} of the "
            "object's size)")
CROSSES = "the hand crosses the support plane at every approach and depth tried"

#: Rounds of line drawing before giving up on reaching ``count`` poses.
ROUNDS = 8

#: A share of lines making a pose below which no further round is drawn (an opening far
#: smaller than the object: :func:`units_warning` says why).
HOPELESS = 0.005


@dataclass(frozen=True, eq=False)
class HandPoses:
    """``N`` jaw poses found by :func:`search_poses`, with the contacts their pads make.

    ``center`` is the jaw centre (on the closing line, between the pads as they
    first touch the object), ``width`` the pads' distance then (the opening to
    command; the contacts lie up to the pads' compliance inside it), ``depth``
    how far the fingertips reach past the centre,
    ``collides`` whether every approach and depth tried meets the object
    (None: not checked); ``attempts`` lines drawn, ``rejected`` the lines
    without a pose, by reason, ``tried`` the hand poses checked, ``lever``
    ``(N, 2)`` each pad's torsional lever (:class:`~forceclosure.gripper.pads.PadContacts`).
    """

    center: NDArray[np.float64]
    closing_axis: NDArray[np.float64]
    approach_axis: NDArray[np.float64]
    width: NDArray[np.float64]
    depth: NDArray[np.float64]
    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    triangles: NDArray[np.int64]
    collides: NDArray[np.bool_] | None
    attempts: int
    lever: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))
    rejected: dict[str, int] = field(default_factory=dict)
    tried: int = 0

    def __len__(self) -> int:
        return len(self.width)


def _spread(count: int) -> NDArray[np.int64]:
    """``0 … count-1`` in an order that spreads them: 0, then halves, quarters, ..."""
    order: list[int] = []
    step = count
    while len(order) < count:
        for k in range(0, count, max(1, step)):
            if k not in order:
                order.append(k)
        step //= 2
        if step == 0:
            step = 1
    return np.array(order, dtype=np.int64)


def depth_values(gripper: ParallelJaw, depths: int) -> NDArray[np.float64]:
    """The fingertip depths tried: the pad's middle first, then spread over the pad
    (strictly inside it), e.g. 1/2, 1/6, 5/6 of the pad's length for 3.

    Examples
    --------
    >>> depth_values(ParallelJaw(1.0, pad_length=0.3), 3).round(3).tolist()
    [0.15, 0.05, 0.25]
    """
    levels = (np.arange(depths) + 0.5) / depths
    order = np.argsort(np.abs(levels - 0.5), kind="stable")
    return gripper.pad_length * levels[order]


def units_warning(gripper: ParallelJaw, size: float) -> str | None:
    """One line when the gripper's opening is far from the object's size (units that
    differ, such as metres against a mesh drawn in millimetres), else None.

    Examples
    --------
    >>> print(units_warning(ParallelJaw(0.08), 2.0))  # doctest: +ELLIPSIS
    the gripper opens 0.08 and the object is 2 across ...: more than 20 times the opening; ...
    >>> units_warning(ParallelJaw(0.08), 0.12) is None
    True
    """
    ratio = size / gripper.width_max
    if ratio > 20:
        return (f"the gripper opens {gripper.width_max:g} and the object is {size:.3g} across "
                "(its bounding box's diagonal): more than 20 times the opening; are both in "
                "the same units? (most poses will be too wide)")
    if ratio < 0.05:
        return (f"the gripper opens {gripper.width_max:g} and the object is {size:.3g} across "
                "(its bounding box's diagonal): less than 1/20 of the opening; are both in the "
                "same units?")
    return None


def _turned(closing: NDArray, approach: NDArray, angle: float) -> NDArray:
    b = np.cross(closing, approach)
    return np.cos(angle) * approach + np.sin(angle) * b


def search_poses(obj: Any, gripper: ParallelJaw, mu: float, count: int, seed: int = 0,
                 approaches: int = APPROACHES, depths: int = DEPTHS,
                 clearance: float | None = None, collision: bool = True,
                 tilt: float = 0.0, support: Any = None) -> HandPoses:
    """Up to ``count`` jaw poses on ``obj`` whose pads hold it, each searched for an
    approach and depth at which ``gripper`` clears the object (module text).

    Parameters
    ----------
    obj : file, bundled name, trimesh.Trimesh or Polyhedron
    gripper : ParallelJaw
    mu : float
        The friction cone the closing lines are drawn in.
    count : int
        Poses wanted (fewer when too few lines make one).
    seed : int
        The same seed gives the same poses.
    approaches, depths : int
        Approach axes and fingertip depths tried per line (1 and 1: no search).
    clearance : float, optional
        How far each pad stands off its contact in the collision check
        (default :data:`~forceclosure.gripper.collision.CLEARANCE` × ``width_max``).
    collision : bool
        Without it nothing is checked: each line keeps its first pose with contacts
        (``collides`` None).
    tilt : float
        The closing lines' spread about the inward normals, as a share (0 to 1) of the
        friction cone's half-angle ``atan(mu)``; 0 (default): along the normals.
    support : SupportPlane, optional
        A table under the object (:mod:`forceclosure.gripper.support`): a pose whose hand
        (its boxes, opened as the collision check opens them) crosses it is never kept,
        not even as a line's colliding fallback; a line where every pose tried crosses
        it makes no pose (counted by reason). Needs the collision check.

    Examples
    --------
    The Panda hand on pybullet_data's duck would need a file; on a 6 cm cube:

    >>> import trimesh
    >>> from forceclosure.gripper.grippers import gripper_named
    >>> cube = trimesh.creation.box(extents=[0.06, 0.06, 0.06])
    >>> poses = search_poses(cube, gripper_named("panda"), mu=0.5, count=20, seed=1)
    >>> len(poses), int(poses.collides.sum()), bool(np.all(poses.width <= 0.08))
    (20, 0, True)
    """
    from .antipodal import draw_lines
    from .collision import collides as hand_collides

    for name, value in (("approaches", approaches), ("depths", depths)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise InputError(f"{name} must be a whole number >= 1, got {value!r}")
    if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 0:
        raise InputError(f"count must be a whole number >= 0, got {count!r}")
    try:
        tilt = float(tilt)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"tilt must be a number from 0 to 1, got {tilt!r}") from None
    if not 0 <= tilt <= 1:
        raise InputError(f"tilt must be a number from 0 to 1, got {tilt!r}")
    if support is not None:
        from .support import SupportPlane

        if not isinstance(support, SupportPlane):
            raise InputError(f"support must be a SupportPlane, got {type(support).__name__}")
        if not collision:
            raise InputError("a support plane is part of the collision check; it has no use "
                             "without it")
    poly, mesh = surface_mesh(obj)
    size = poly.size
    angles = 2 * np.pi * _spread(int(approaches)) / int(approaches)
    levels = depth_values(gripper, int(depths))
    combos = [(a, d) for a in angles for d in levels]
    reach = pad_reach(levels, gripper.pad_length, gripper.pad_height)
    rng = np.random.default_rng(seed)
    kept: list[dict[str, NDArray]] = []
    found, attempts, tried = 0, 0, 0
    rejected: dict[str, int] = {}
    for _ in range(ROUNDS):
        rate = found / attempts if attempts else 1.0
        if found >= count or rate < HOPELESS:
            break
        m = int(np.ceil((count - found) / max(rate, 0.02) * 1.1)) + 8
        origin, closing, approach0 = draw_lines(mesh, mu, m, rng, tilt)
        attempts += m
        line_of, tri_of = line_candidates(mesh, origin, closing, reach)
        order = np.argsort(line_of, kind="stable")
        line_of, tri_of = line_of[order], tri_of[order]
        starts = np.searchsorted(line_of, np.arange(m + 1))
        settled = np.zeros(m, bool)
        have = np.zeros(m, bool)  # a pose with contacts, kept as the fallback
        result = {"center": np.zeros((m, 3)), "approach": np.zeros((m, 3)),
                  "width": np.zeros(m), "depth": np.zeros(m), "points": np.zeros((m, 2, 3)),
                  "normals": np.zeros((m, 2, 3)), "triangles": np.full((m, 2), -1),
                  "collides": np.ones(m, bool), "lever": np.zeros((m, 2))}
        why = np.full(m, None, dtype=object)
        why[:] = NOTHING
        for angle, depth in combos:
            active = np.flatnonzero(~settled)
            if not len(active):
                break
            approach = _turned(closing[active], approach0[active], angle)
            counts = starts[active + 1] - starts[active]
            pose_of = np.repeat(np.arange(len(active)), counts)
            tri = tri_of[np.concatenate([np.arange(starts[i], starts[i + 1]) for i in active])
                         ] if counts.sum() else np.zeros(0, np.int64)
            pc = pad_contacts(mesh, origin[active], closing[active], approach,
                              np.full(len(active), depth), gripper.pad_length,
                              gripper.pad_height, pose_of, tri, size, gripper.pad_compliance,
                              levers=False)
            y = pc.first  # the pads' faces as they meet the object
            width = y[:, 1] - y[:, 0]
            ok = pc.holds(gripper.width_max, size)
            wide = pc.touched & (width > gripper.width_max)
            thin = pc.touched & ~wide & ~ok
            why[active[wide & (why[active] == NOTHING)]] = TOO_WIDE
            why[active[thin & (why[active] == NOTHING)]] = COINCIDE
            sel = np.flatnonzero(ok)
            if not len(sel):
                continue
            lines = active[sel]
            center = origin[lines] + 0.5 * (y[sel, 0] + y[sel, 1])[:, None] * closing[lines]
            if support is not None:  # through the table: no pose at all
                from .support import crosses_plane

                through = crosses_plane(support, gripper, center, closing[lines],
                                        approach[sel], width[sel],
                                        np.full(len(sel), depth), clearance)
                why[lines[through & ~have[lines]]] = CROSSES
                keep = ~through
                sel, lines, center = sel[keep], lines[keep], center[keep]
                if not len(sel):
                    continue
            if collision:
                tried += len(sel)
                hit = np.asarray(hand_collides(
                    poly, _Arrays(center, closing[lines], approach[sel], width[sel]),
                    gripper, clearance, depths=np.full(len(sel), depth)), dtype=bool)
            else:
                hit = np.zeros(len(sel), bool)
            take = ~hit | ~have[lines]  # a clear pose, or the first with contacts
            rows = lines[take]
            found_now = {"center": center, "approach": approach[sel], "width": width[sel],
                         "depth": np.full(len(sel), depth), "points": pc.points[sel],
                         "normals": pc.normals[sel], "triangles": pc.triangles[sel],
                         "collides": hit}
            for key, value in found_now.items():
                result[key][rows] = value[take]
            have[lines] = True
            settled[lines[~hit]] = True
            if not collision:
                settled[lines] = True
        good = np.flatnonzero(have)[: count - found]
        # the kept poses' torsional levers, once (the search above needs none)
        counts = starts[good + 1] - starts[good]
        tri = (tri_of[np.concatenate([np.arange(starts[i], starts[i + 1]) for i in good])]
               if counts.sum() else np.zeros(0, np.int64))
        kept_pads = pad_contacts(mesh, origin[good], closing[good], result["approach"][good],
                                 result["depth"][good], gripper.pad_length, gripper.pad_height,
                                 np.repeat(np.arange(len(good)), counts), tri, size,
                                 gripper.pad_compliance)
        result["lever"][good] = kept_pads.lever
        for r in why[~have]:
            rejected[r] = rejected.get(r, 0) + 1
        found += len(good)
        kept.append({**{k: v[good] for k, v in result.items()}, "closing": closing[good]})
    cat = {k: np.concatenate([part[k] for part in kept]) for k in kept[0]} if kept else {}
    if not cat or not len(cat["width"]):
        cat = {"center": np.zeros((0, 3)), "closing": np.zeros((0, 3)),
               "approach": np.zeros((0, 3)), "width": np.zeros(0), "depth": np.zeros(0),
               "points": np.zeros((0, 2, 3)), "normals": np.zeros((0, 2, 3)),
               "triangles": np.zeros((0, 2), np.int64), "collides": np.zeros(0, bool),
               "lever": np.zeros((0, 2))}
    return HandPoses(cat["center"], cat["closing"], cat["approach"], cat["width"],
                     cat["depth"], cat["points"], cat["normals"],
                     cat["triangles"].astype(np.int64),
                     cat["collides"].astype(bool) if collision else None,
                     attempts, rejected=rejected, tried=tried, lever=cat["lever"])


class _Arrays:
    """Arrays of jaw poses, as :func:`~forceclosure.gripper.collision.collides` reads them."""

    def __init__(self, center, closing_axis, approach_axis, width):
        self.center, self.closing_axis = center, closing_axis
        self.approach_axis, self.width = approach_axis, width
