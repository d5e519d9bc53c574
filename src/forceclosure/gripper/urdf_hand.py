"""A user's parallel-jaw hand from its URDF: :func:`gripper_from_urdf`.

The hand is read as the URDF describes it and measured into the boxes of a
:class:`~forceclosure.gripper.jaw.ParallelJaw` (the jaw frame of
:mod:`forceclosure.gripper.collision`: x the approach axis, y the closing
axis, z = x × y):

* **fingers**: the children of the URDF's two prismatic joints (or the two
  links named by ``finger_links``), each with the links fixed below it. A
  finger that turns (a revolute or continuous joint on its way from the
  palm) is refused: the model is of fingers that slide parallel;
* **palm**: the hand's root link, named by ``palm_link`` or found as the
  nearest common parent of the two fingers (a robot's arm above it is left
  out), with the links fixed below it. Its frame is the hand's base frame
  (ACRONYM's gripper frame: for the Panda, ``panda_hand``);
* **closing axis**: the prismatic joints' axes, in the palm's frame (they
  must be parallel); **opening**: each finger joint at the limit that moves
  its finger away from the other (mimic joints follow their joint), and
  ``width_max`` the distance between the two pads' planes there: for two
  mirrored joints that is twice the upper limit, plus whatever gap the
  fingers leave when closed;
* **approach axis**: from the palm's origin towards the fingers (the mean of
  the two fingers' bounding-box centres, perpendicular to the closing axis),
  taken as the palm frame's axis when within :data:`SNAP_DEGREES` of one; or
  ``approach`` as given;
* **pads**: the faces of each finger's inner side that lie within
  :data:`FLAT_RTOL` of the hand's size of its innermost plane and face the
  other finger within :data:`FLAT_DEGREES`; the pad runs from the fingertips
  back to the flat part's far end (``pad_length``) and is as high as the flat
  part reaches on both sides of the fingers' mid-plane (``pad_height``);
  the jaw centre is the pad's middle (``depth = pad_length / 2``);
* **boxes**: every extent is the geometry's, taken so that the boxes enclose
  the hand (never smaller): ``tip_offset`` from the palm's origin to the
  fingertips along the approach; ``finger_length`` the part of the fingers
  in front of the palm; ``finger_thickness`` from the pad's plane to the
  finger's outer side; ``finger_height``, ``palm_width`` and
  ``palm_height`` twice the farthest any vertex lies from the jaw's
  mid-planes; the palm box reaches from its back face to the fingers'
  free part, and also holds the fingers' bases when they sit inside it.

Geometry is read by :func:`forceclosure.objects.urdf.link_geometry` (collision
elements, else visual ones; boxes, cylinders, spheres and meshes, with the
same checks and the same refusal of meshes outside the URDF's folder).
Anything the model cannot stand for is refused in one line: no or ambiguous
finger joints, turning fingers, closing axes that are not parallel,
fingers that do not close across the palm's approach line (off it by more
than :data:`CENTRE_RTOL` of the opening), pads that do not face each other.
Lengths are the URDF's (metres).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .jaw import ParallelJaw

__all__ = ["CENTRE_RTOL", "FLAT_DEGREES", "FLAT_RTOL", "SNAP_DEGREES", "gripper_from_urdf",
           "is_urdf_name"]

#: A pad's faces lie within this share of the hand's size (its bounding-box diagonal) of the
#: finger's innermost plane.
FLAT_RTOL = 1e-3

#: A pad's faces turn at most this far (degrees) from facing the other finger.
FLAT_DEGREES = 5.0

#: An approach axis found within this many degrees of a palm-frame axis is taken as that axis.
SNAP_DEGREES = 5.0

#: The pads' midpoint may lie off the palm's approach line by this share of the opening.
CENTRE_RTOL = 0.01

#: Prismatic joints' axes are parallel when their directions differ by less than this (radians).
PARALLEL_RADIANS = 1e-3


def is_urdf_name(name: object) -> bool:
    """Whether a ``--gripper`` value names a URDF file (it ends in ``.urdf``).

    Examples
    --------
    >>> is_urdf_name("robots/hand.URDF"), is_urdf_name("panda")
    (True, False)
    """
    return isinstance(name, str) and name.lower().endswith(".urdf")


@dataclass(frozen=True)
class _Joint:
    name: str
    kind: str
    parent: str
    child: str
    origin: NDArray[np.float64]  # 4 x 4
    axis: NDArray[np.float64]  # unit, in the joint's frame
    lower: float
    upper: float
    mimic: str | None
    multiplier: float
    offset: float


def _joints(root: ET.Element, where: str) -> list[_Joint]:
    from ..objects.urdf import origin_transform, urdf_numbers

    joints = []
    for index, element in enumerate(root.findall("joint")):
        name = element.get("name") or f"joint {index + 1}"
        at = f"{where}: joint {name!r}"
        kind = element.get("type", "")
        parent, child = element.find("parent"), element.find("child")
        parent_link = None if parent is None else parent.get("link")
        child_link = None if child is None else child.get("link")
        if not parent_link or not child_link:
            raise InputError(f"{at}: needs <parent link> and <child link>")
        origin = element.find("origin")
        xyz = urdf_numbers(origin.get("xyz", "0 0 0") if origin is not None else "0 0 0", (3,),
                           "origin xyz", at)
        rpy = urdf_numbers(origin.get("rpy", "0 0 0") if origin is not None else "0 0 0", (3,),
                           "origin rpy", at)
        axis_element = element.find("axis")
        axis = np.array([1.0, 0.0, 0.0])
        if kind in ("prismatic", "revolute", "continuous"):
            if axis_element is not None:
                axis = urdf_numbers(axis_element.get("xyz", "1 0 0"), (3,), "axis xyz", at)
            norm = float(np.linalg.norm(axis))
            if norm <= 1e-12:
                raise InputError(f"{at}: its axis is zero")
            axis = axis / norm
        lower = upper = 0.0
        limit = element.find("limit")
        if kind in ("prismatic", "revolute"):
            if limit is None:
                raise InputError(f"{at}: a {kind} joint needs <limit>")
            lower = float(urdf_numbers(limit.get("lower", "0"), (1,), "limit lower", at)[0])
            upper = float(urdf_numbers(limit.get("upper", "0"), (1,), "limit upper", at)[0])
            if lower > upper:
                raise InputError(f"{at}: limit lower {lower:g} is above upper {upper:g}")
        mimic = element.find("mimic")
        multiplier, offset = 1.0, 0.0
        if mimic is not None:
            if not mimic.get("joint"):
                raise InputError(f"{at}: <mimic> names no joint")
            multiplier = float(urdf_numbers(mimic.get("multiplier", "1"), (1,), "mimic multiplier",
                                            at)[0])
            offset = float(urdf_numbers(mimic.get("offset", "0"), (1,), "mimic offset", at)[0])
        joints.append(_Joint(name, kind, parent_link, child_link,
                             origin_transform(xyz, rpy), axis, lower, upper,
                             None if mimic is None else mimic.get("joint"), multiplier, offset))
    return joints


class _Tree:
    """The URDF's links and joints: who hangs below whom."""

    def __init__(self, root: ET.Element, where: str):
        self.where = where
        self.links = [link.get("name") for link in root.findall("link")]
        self.joints = _joints(root, where)
        self.by_name = {j.name: j for j in self.joints}
        self.above: dict[str, _Joint] = {}
        for j in self.joints:
            if j.child in self.above:
                raise InputError(f"{where}: link {j.child!r} hangs from two joints "
                                 f"({self.above[j.child].name}, {j.name})")
            self.above[j.child] = j
        for name in {j.parent for j in self.joints} | {j.child for j in self.joints}:
            if name not in self.links:
                raise InputError(f"{where}: a joint names link {name!r}, which is not in the "
                                 "file")

    def check_link(self, name: str, option: str) -> None:
        if name not in self.links:
            raise InputError(f"{self.where}: {option}: no link named {name!r}; the links are "
                             + ", ".join(str(n) for n in self.links[:20]))

    def chain(self, link: str) -> list[_Joint]:
        """The joints from the root down to ``link``."""
        out, seen = [], set()
        while link in self.above:
            if link in seen:
                raise InputError(f"{self.where}: the joints make a loop at link {link!r}")
            seen.add(link)
            out.append(self.above[link])
            link = self.above[link].parent
        return out[::-1]

    def ancestors(self, link: str) -> list[str]:
        """``link`` and the links above it, nearest first."""
        return [link] + [j.parent for j in reversed(self.chain(link))]

    def fixed_below(self, link: str, stop: set[str]) -> tuple[list[str], list[_Joint]]:
        """The links fixed below ``link`` (itself included), and the moving joints met below
        them (not followed); links in ``stop`` are not entered."""
        links, moving, todo = [], [], [link]
        while todo:
            name = todo.pop()
            links.append(name)
            for j in self.joints:
                if j.parent != name or j.child in stop:
                    continue
                if j.kind == "fixed":
                    todo.append(j.child)
                else:
                    moving.append(j)
        return links, moving


def _motion(joint: _Joint, q: float) -> NDArray[np.float64]:
    """The joint's transform at position ``q``: its origin, then its sliding."""
    slide = np.eye(4)
    if joint.kind == "prismatic":
        slide[:3, 3] = joint.axis * q
    elif joint.kind != "fixed":
        raise InputError(f"joint {joint.name!r}: a {joint.kind} joint is not modelled")
    return joint.origin @ slide


def _transform(path: list[_Joint], q: dict[str, float]) -> NDArray[np.float64]:
    """From the first joint's parent's frame to the last one's child's, joints at ``q``."""
    T = np.eye(4)
    for joint in path:
        T = T @ _motion(joint, q.get(joint.name, 0.0))
    return T


def _vertices(urdf: Path, links: list[str], allow_outside_meshes: bool
              ) -> dict[str, tuple[NDArray, NDArray]]:
    """Each link's geometry (vertices, triangles) in its own frame; links without any left
    out."""
    from ..objects.urdf import link_geometry

    out = {}
    for link in links:
        try:
            _, pieces, _ = link_geometry(urdf, part=link,
                                         allow_outside_meshes=allow_outside_meshes)
        except InputError as e:
            if "has no collision or visual geometry" in str(e):
                continue
            raise
        V, T, base = [], [], 0
        for piece in pieces:
            V.append(piece.vertices)
            T.append(piece.triangles + base)
            base += len(piece.vertices)
        out[link] = (np.concatenate(V), np.concatenate(T))
    return out


def _placed(tree: _Tree, palm: str, links: list[str], geometry: dict, q: dict[str, float]
            ) -> tuple[NDArray, NDArray]:
    """The geometry of ``links`` in the palm's frame at joint positions ``q``."""
    V, T, base = [np.zeros((0, 3))], [np.zeros((0, 3), dtype=np.int64)], 0
    below = len(tree.chain(palm))
    for link in links:
        if link not in geometry:
            continue
        M = _transform(tree.chain(link)[below:], q)
        v, t = geometry[link]
        V.append(v @ M[:3, :3].T + M[:3, 3])
        T.append(t + base)
        base += len(v)
    return np.concatenate(V), np.concatenate(T)


def _direction(tree: _Tree, palm: str, joint: _Joint) -> NDArray[np.float64]:
    """A prismatic joint's axis in the palm's frame (joints at 0)."""
    below = len(tree.chain(palm))
    path = tree.chain(joint.child)[below:]
    return _transform(path, {})[:3, :3] @ joint.axis


def gripper_from_urdf(path: str | Path, *, finger_links: tuple[str, str] | None = None,
                      palm_link: str | None = None, approach: ArrayLike | None = None,
                      name: str | None = None, pad_radius: float | None = None,
                      pad_compliance: float | None = None,
                      allow_outside_meshes: bool = False) -> ParallelJaw:
    """A :class:`~forceclosure.gripper.jaw.ParallelJaw` measured from a hand's URDF (module
    text: what is taken from where).

    Parameters
    ----------
    path : str or Path
        The ``.urdf`` file (a hand, or a robot with a hand).
    finger_links : (str, str), optional
        The two finger links, jaw 1's first (default: the children of the file's two
        prismatic joints; refused when there are not exactly two).
    palm_link : str, optional
        The hand's root link, whose frame is the hand's base frame (default: the nearest
        common parent of the fingers).
    approach : 3 numbers, optional
        The approach axis in the palm's frame (default: from the palm's origin towards the
        fingers).
    name : str, optional
        The hand's name (default: the URDF's robot name, else the file's stem).
    pad_radius, pad_compliance : float, optional
        As for :class:`~forceclosure.gripper.jaw.ParallelJaw` (not in a URDF).
    allow_outside_meshes : bool
        Read meshes outside the URDF's folder (or its package's).

    Raises
    ------
    InputError
        In one line, when the file cannot be read or the hand is not one the model stands
        for (module text).

    Examples
    --------
    >>> import pybullet_data
    >>> hand = gripper_from_urdf(pybullet_data.getDataPath() + "/franka_panda/panda.urdf")
    >>> hand.name, round(hand.width_max, 4), round(hand.tip_offset, 4)
    ('panda', 0.0797, 0.1122)
    >>> gripper_from_urdf(pybullet_data.getDataPath() + "/pr2_gripper.urdf")
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: pr2_gripper.urdf: no prismatic joints, only turning ones ...
    """
    from ..objects.urdf import robot_element

    urdf = Path(path)
    where = urdf.name
    if not urdf.is_file():
        raise InputError(f"{path}: no such URDF file")
    root = robot_element(urdf)
    tree = _Tree(root, where)
    turning = [j.name for j in tree.joints if j.kind in ("revolute", "continuous")]
    prismatic = [j for j in tree.joints if j.kind == "prismatic"]
    if finger_links is None:
        if len(prismatic) != 2:
            if not tree.joints:
                raise InputError(f"{where}: {len(tree.links)} link"
                                 f"{'s' if len(tree.links) != 1 else ''} and no joints: a "
                                 "single part, not a hand with two fingers")
            if not prismatic and turning:
                raise InputError(f"{where}: no prismatic joints, only turning ones "
                                 f"({', '.join(turning[:4])}"
                                 f"{', ...' if len(turning) > 4 else ''}): not a parallel-jaw "
                                 "hand (its fingers must slide on prismatic joints)")
            listed = ", ".join(j.name for j in prismatic[:6]) or "none"
            raise InputError(f"{where}: {len(prismatic)} prismatic joints ({listed}), not the "
                             "two of a parallel-jaw hand's fingers; name the finger links "
                             "(finger_links=)")
        fingers = (prismatic[0].child, prismatic[1].child)
    else:
        if (isinstance(finger_links, str) or len(finger_links) != 2
                or len(set(finger_links)) != 2):
            raise InputError(f"{where}: finger_links: two different links are needed, got "
                             f"{finger_links!r}")
        fingers = (str(finger_links[0]), str(finger_links[1]))
        for f in fingers:
            tree.check_link(f, "finger_links")
    # the palm: the nearest common parent, or the one named (above both fingers)
    up = [tree.ancestors(f) for f in fingers]
    if palm_link is None:
        common = [link for link in up[0][1:] if link in up[1][1:]]
        if not common:
            raise InputError(f"{where}: the fingers {fingers[0]!r} and {fingers[1]!r} hang from "
                             "no common link; name the palm (palm_link=)")
        palm = common[0]
    else:
        tree.check_link(palm_link, "palm_link")
        if any(palm_link not in chain[1:] for chain in up):
            raise InputError(f"{where}: palm_link {palm_link!r} is not above both fingers "
                             f"({fingers[0]!r}, {fingers[1]!r})")
        palm = palm_link
    below = len(tree.chain(palm))
    # each finger's way down from the palm: fixed joints and at most one prismatic one
    drives: list[_Joint | None] = []
    groups: list[list[str]] = []
    for f in fingers:
        path_joints = tree.chain(f)[below:]
        bad = [j for j in path_joints if j.kind not in ("fixed", "prismatic")]
        if bad:
            kind = "revolute" if bad[0].kind in ("revolute", "continuous") else bad[0].kind
            raise InputError(f"{where}: finger {f!r} moves on the {kind} joint {bad[0].name!r}: "
                             "not a parallel-jaw finger (only prismatic fingers are modelled)")
        slides = [j for j in path_joints if j.kind == "prismatic"]
        if len(slides) > 1:
            raise InputError(f"{where}: finger {f!r} slides on {len(slides)} prismatic joints "
                             f"({', '.join(j.name for j in slides)}); one is modelled")
        drives.append(slides[0] if slides else None)
        top = slides[0].child if slides else f
        links, moving = tree.fixed_below(top, stop=set())
        if moving:
            raise InputError(f"{where}: finger {f!r} carries the {moving[0].kind} joint "
                             f"{moving[0].name!r}: jointed fingers are not modelled")
        groups.append(links)
    if drives[0] is None and drives[1] is None:
        raise InputError(f"{where}: neither finger ({fingers[0]!r}, {fingers[1]!r}) slides on a "
                         "prismatic joint")
    finger_set = set(groups[0]) | set(groups[1])
    palm_links, moving = tree.fixed_below(palm, stop=finger_set)
    if moving:
        raise InputError(f"{where}: the palm {palm!r} carries the {moving[0].kind} joint "
                         f"{moving[0].name!r} besides the fingers': not modelled (name the "
                         "fingers and the palm: finger_links=, palm_link=)")
    if set(groups[0]) & set(groups[1]):
        raise InputError(f"{where}: the fingers {fingers[0]!r} and {fingers[1]!r} share links")
    # the closing axis
    sliding = [j for j in drives if j is not None]
    axes = [_direction(tree, palm, j) for j in sliding]
    if len(axes) == 2 and abs(float(axes[0] @ axes[1])) < math.cos(PARALLEL_RADIANS):
        angle = math.degrees(math.acos(min(1.0, abs(float(axes[0] @ axes[1])))))
        raise InputError(f"{where}: the finger joints {sliding[0].name!r} and "
                         f"{sliding[1].name!r} slide along axes {angle:.3g} degrees apart: not "
                         "a parallel-jaw hand")
    closing = axes[0]
    # the positions of the driving joints: each at either limit; mimic joints follow
    masters: dict[str, _Joint] = {}
    for j in drives:
        if j is None:
            continue
        m = tree.by_name.get(j.mimic) if j.mimic else j
        if m is None:
            raise InputError(f"{where}: joint {j.name!r} mimics {j.mimic!r}, which is not in "
                             "the file")
        masters[m.name] = m
    geometry = _vertices(urdf, sorted(set(palm_links) | finger_set, key=str),
                         allow_outside_meshes)
    for f, links in zip(fingers, groups, strict=True):
        if not any(link in geometry for link in links):
            raise InputError(f"{where}: finger {f!r} has no collision or visual geometry")

    def config(choice: tuple[int, ...]) -> dict[str, float]:
        q = {}
        for (mname, m), pick in zip(masters.items(), choice, strict=True):
            q[mname] = m.upper if pick else m.lower
        for j in drives:
            if j is not None and j.mimic:
                q[j.name] = j.multiplier * q[j.mimic] + j.offset
        return q

    def centre(links: list[str], q: dict[str, float]) -> NDArray[np.float64]:
        V, _ = _placed(tree, palm, links, geometry, q)
        return 0.5 * (V.min(axis=0) + V.max(axis=0))

    choices = [tuple((k >> i) & 1 for i in range(len(masters))) for k in range(2**len(masters))]
    spread = [float((centre(groups[1], config(c)) - centre(groups[0], config(c))) @ closing)
              for c in choices]
    best = int(np.argmax(np.abs(spread)))
    q_open = config(choices[best])
    if spread[best] < 0:
        closing = -closing  # from jaw 1 (the first finger) to jaw 2
    fingers_open = [_placed(tree, palm, links, geometry, q_open) for links in groups]
    palm_V, _ = _placed(tree, palm, palm_links, geometry, q_open)
    # the approach axis
    if approach is None:
        mid = 0.5 * (centre(groups[0], q_open) + centre(groups[1], q_open))
        a = mid - (mid @ closing) * closing
        if np.linalg.norm(a) <= 1e-9 * max(1.0, float(np.linalg.norm(mid))):
            raise InputError(f"{where}: the fingers sit on the palm's closing line; give the "
                             "approach axis (approach=)")
        a = a / np.linalg.norm(a)
        for axis in np.vstack([np.eye(3), -np.eye(3)]):
            if abs(axis @ closing) < 1e-9 and axis @ a >= math.cos(math.radians(SNAP_DEGREES)):
                a = axis.copy()
                break
    else:
        try:
            a = np.asarray(approach, dtype=float).reshape(3)
        except (TypeError, ValueError):
            raise InputError(f"{where}: approach must be 3 numbers, got {approach!r}") from None
        a = a - (a @ closing) * closing
        if not np.all(np.isfinite(a)) or np.linalg.norm(a) <= 1e-9:
            raise InputError(f"{where}: approach {np.asarray(approach).tolist()} is parallel to "
                             f"the closing axis {closing.round(6).tolist()}")
        a = a / np.linalg.norm(a)
    R = np.column_stack([a, closing, np.cross(a, closing)])  # jaw frame -> palm frame
    jaw = [(V @ R, T) for V, T in fingers_open]
    palm_J = palm_V @ R
    everything = np.concatenate([palm_J] + [V for V, _ in jaw])
    size = float(np.linalg.norm(everything.max(axis=0) - everything.min(axis=0)))
    tol = FLAT_RTOL * size
    # the pads: each finger's innermost flat faces, turned towards the other finger
    inner, pads = [], []
    for k, (V, T) in enumerate(jaw):
        toward = 1.0 if k == 0 else -1.0  # jaw 1 faces +y, jaw 2 faces -y
        plane = float((toward * V[:, 1]).max())
        e1, e2 = V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]
        n = np.cross(e1, e2)
        area = np.linalg.norm(n, axis=1)
        ok = area > 1e-15 * size**2
        cos = np.zeros(len(T))
        cos[ok] = np.abs(n[ok, 1]) / area[ok]
        on = np.all(toward * V[T][:, :, 1] >= plane - tol, axis=1)
        flat = ok & on & (cos >= math.cos(math.radians(FLAT_DEGREES)))
        if not flat.any():
            raise InputError(f"{where}: finger {fingers[k]!r} has no flat face on its inner side "
                             "facing the other finger: no pad to model")
        inner.append(toward * plane)
        pads.append(V[T[flat]].reshape(-1, 3))
    width = inner[1] - inner[0]
    if not width > 0:
        raise InputError(f"{where}: the fingers do not open (their pads are {width:g} apart at "
                         "the joints' limits)")
    centre_y = 0.5 * (inner[0] + inner[1])
    if abs(centre_y) > CENTRE_RTOL * width:
        raise InputError(f"{where}: the fingers close {abs(centre_y):.3g} off the palm's "
                         f"approach line (more than {CENTRE_RTOL:g} of the opening "
                         f"{width:.3g}); not modelled")
    finger_all = np.concatenate([V for V, _ in jaw])
    tip = float(finger_all[:, 0].max())
    base = float(finger_all[:, 0].min())
    thickness = max(inner[0] - float(jaw[0][0][:, 1].min()),
                    float(jaw[1][0][:, 1].max()) - inner[1])
    finger_height = 2 * float(np.abs(finger_all[:, 2]).max())
    if len(palm_J):
        front = max(float(palm_J[:, 0].max()), base)
        finger_length = tip - front
        if not finger_length > 0:
            raise InputError(f"{where}: the fingers do not reach past the palm")
        held = [palm_J] + ([finger_all] if base < front else [])
        behind = np.concatenate(held)
        palm_thickness = front - float(behind[:, 0].min())
        palm_width = 2 * float(np.abs(behind[:, 1] - centre_y).max())
        palm_height = 2 * float(np.abs(behind[:, 2]).max())
    else:
        front, finger_length = base, tip - base
        palm_thickness, palm_width, palm_height = 0.0, None, None
    pad_start = max(float(p[:, 0].min()) for p in pads)
    pad_length = min(tip - pad_start, finger_length)
    pad_height = 2 * min(min(-float(p[:, 2].min()), float(p[:, 2].max())) for p in pads)
    if not pad_height > 0:
        raise InputError(f"{where}: the pads do not cross the fingers' mid-plane (z = 0 in the "
                         "jaw frame): not modelled")
    robot = root.get("name")
    return ParallelJaw(
        float(width), pad_radius, name=name or (robot.strip() if robot and robot.strip()
                                               else urdf.stem),
        depth=0.5 * pad_length, finger_length=finger_length, finger_thickness=thickness,
        finger_height=finger_height, palm_thickness=palm_thickness, palm_width=palm_width,
        palm_height=palm_height, pad_length=pad_length, pad_height=pad_height,
        tip_offset=tip, pad_compliance=pad_compliance)
