"""Contacts of a body in a pybullet scene, as forceclosure contacts.

pybullet's ``getContactPoints`` reports, for every manifold point between
bodies A and B, ``positionOnA``, ``positionOnB`` and ``contactNormalOnB``,
the normal of B's surface **pointing from B towards A**. The object may be
either body of a row: as body B its outward normal is ``contactNormalOnB``
and its surface point ``positionOnB``; as body A its outward normal is
``-contactNormalOnB`` and its surface point ``positionOnA``.

Friction is the coefficient Bullet itself puts on the contact: the product of
the two links' ``lateralFriction`` (``getDynamicsInfo(...)[1]``), clipped to
``[-10, 10]`` — ``btManifoldResult::calculateCombinedFriction`` in
bullet3's ``src/BulletCollision/CollisionDispatch/btManifoldResult.cpp``.
Bullet bounds the two tangential impulses separately by ``mu`` times the
normal impulse (a square around the circle of radius ``mu``), so the circular
cone analysed here lies inside the one Bullet simulates. A soft finger's
torsional coefficient is Bullet's combined spinning friction,
``spinning_A * lateral_B + spinning_B * lateral_A`` clipped to ``[-10, 10]``
(``calculateCombinedSpinningFriction``, same file; ``getDynamicsInfo(...)[7]``),
a length: the spin torque is bounded by it times the normal force. (Bullet's
solver for maximal-coordinate rigid bodies also caps that torque impulse at
the coefficient itself; multibodies, pybullet's default, have no such cap.)
Rolling friction is not represented. Bullet applies spinning friction only where that
combined coefficient is positive; a soft finger asked for (``contact_model="soft"``) where it
is 0 (pybullet's default ``spinningFriction`` is 0) would be a hard finger under another
name, so it is refused in one line naming the bodies (set ``spinningFriction`` with
``changeDynamics``, give ``torsion=``, or take ``"hard"``).

Bullet bounds the two tangential impulses and the spin impulse each on its own (a box
around the circle, and an interval), so the analysed cone (a circular cone, times the
torsion interval for soft fingers) lies inside the one Bullet simulates with the
coefficients as they are: ``friction="inner"`` (the MuJoCo adapter's option) changes
nothing here.

Points and normals are in the world frame (``positionOnA/B`` and ``contactNormalOnB`` are),
not the object's: analyse them as they are, or move them into the object's frame with its
pose (``getBasePositionAndOrientation``) first.

Bullet keeps at most four points per pair of shapes, not always the whole
contact face (a box dropped exactly flat on a ``GEOM_PLANE`` had two, on
``plane.urdf`` four); the adapter reports what Bullet has, each repeated
point once (see :func:`forceclosure.simulators._merge.contacts_from_rows`).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from ..contacts import Contact, Model
from ..errors import InputError
from ._merge import MERGE, Friction, check_options, contacts_from_rows, one_of

__all__ = ["contacts_from_pybullet"]

#: Bullet's clip on combined friction coefficients (btManifoldResult.cpp, MAX_FRICTION).
MAX_FRICTION = 10.0


def _connected(pb: Any, client: object) -> int:
    if not isinstance(client, int) or isinstance(client, bool):
        raise InputError(f"pybullet: 'client' must be a physics client id (an int), got "
                         f"{client!r}")
    if not pb.isConnected(physicsClientId=client):
        raise InputError(f"pybullet: client {client} is not connected")
    return client


def _body(pb: Any, body: object, client: int, field: str) -> int:
    if not isinstance(body, int | np.integer) or isinstance(body, bool):
        raise InputError(f"pybullet: '{field}' must be a body id (an int), got {body!r}")
    try:
        pb.getBodyInfo(int(body), physicsClientId=client)
    except pb.error:
        raise InputError(f"pybullet: no body with id {body} in client {client} "
                         f"('{field}')") from None
    return int(body)


def _finger(pb: Any, finger: object, client: int, field: str) -> tuple[int, int | None]:
    """A finger as ``(body, link)``: a body id (every link, ``link`` None) or a pair
    ``(body id, link index)``, -1 being the base."""
    if isinstance(finger, tuple | list):
        if len(finger) != 2:
            raise InputError(f"pybullet: each of '{field}' must be a body id or a pair "
                             f"(body id, link index), got {finger!r}")
        body, link = finger
        body = _body(pb, body, client, field)
        links = pb.getNumJoints(body, physicsClientId=client)
        if (not isinstance(link, int | np.integer) or isinstance(link, bool)
                or not -1 <= int(link) < links):
            raise InputError(f"pybullet: body {body} has no link {link!r} ('{field}'; its "
                             f"links are -1 to {links - 1})")
        return body, int(link)
    return _body(pb, finger, client, field), None


def contacts_from_pybullet(body: int | None = None, client: int = 0, *,
                           link: int | None = None,
                           fingers: Iterable[int | tuple[int, int]] | None = None,
                           contact_model: Model | None = None, mu: float | None = None,
                           torsion: float | None = None, friction: Friction = "nominal",
                           max_distance: float = 0.0, merge: float = MERGE,
                           object_id: int | None = None, other_ids: Iterable[int] | None = None,
                           model: Model | None = None) -> list[Contact]:
    """The contacts on body ``body`` in pybullet client ``client``, in the world frame.

    Read after ``stepSimulation`` (or ``performCollisionDetection``): each
    manifold point touching the object becomes a point contact at the point
    on the object's surface, with the object's outward normal there (see the
    module's notes for the sign of ``contactNormalOnB``). Points and normals
    are in the world frame, as pybullet reports them.

    The keyword options are those of :func:`contacts_from_mujoco`, by the
    same names: ``fingers``, ``contact_model``, ``mu``, ``torsion``,
    ``friction``, ``max_distance``, ``merge``.

    Parameters
    ----------
    body : int
        The body being grasped (older name: ``object_id``, still accepted).
    client : int
        The physics client (``pybullet.connect``'s result); 0 by default.
    link : int, optional
        Keep only contacts on this link of the object (-1: its base).
    fingers : iterable, optional
        Keep only contacts with these: body ids (every link of the body) or
        pairs ``(body id, link index)`` (one link: a finger of a hand that is
        one multibody). Older name: ``other_ids`` (body ids), still accepted.
    contact_model : {"hard", "soft", "frictionless"}, optional
        The contact model of every contact (older name: ``model``, still
        accepted); default ``"hard"`` (Bullet has no per-contact condim). A
        soft finger takes Bullet's combined spinning friction as its
        torsional coefficient; where that is 0, ``"soft"`` is refused
        unless ``torsion`` is given (see the module's notes).
    mu, torsion : float, optional
        Override Bullet's combined friction and (soft fingers) combined
        spinning friction for every contact.
    friction : {"nominal", "inner"}
        Accepted for the MuJoCo adapter's sake; the same here (Bullet's
        cone holds the analysed one already).
    max_distance : float
        Points farther apart than this (``contactDistance``, negative when
        penetrating) are not touching and are left out.
    merge : float
        Points within ``merge`` of each other, with normals within ``merge``
        radians, are one contact (kept once, with the smaller coefficients).

    Returns
    -------
    list of Contact
        Ready for :func:`forceclosure.analyze`; world coordinates.

    Raises
    ------
    InputError
        The client is not connected, a body id or link is unknown, an
        option is bad or given twice (by both its names), a soft finger has
        no spinning friction, or the object has no contact left after the
        filters (one line each).

    References
    ----------
    .. [1] E. Coumans and Y. Bai, "PyBullet, a Python module for physics simulation for
       games, robotics and machine learning", http://pybullet.org, 2016-2021

    Examples
    --------
    >>> import pybullet as pb
    >>> client = pb.connect(pb.DIRECT)
    >>> floor = pb.createMultiBody(0, pb.createCollisionShape(
    ...     pb.GEOM_PLANE, physicsClientId=client), physicsClientId=client)
    >>> box = pb.createMultiBody(1, pb.createCollisionShape(
    ...     pb.GEOM_BOX, halfExtents=[0.1] * 3, physicsClientId=client),
    ...     basePosition=[0, 0, 0.1], physicsClientId=client)
    >>> pb.setGravity(0, 0, -10, physicsClientId=client)
    >>> for _ in range(50):
    ...     _ = pb.stepSimulation(physicsClientId=client)
    >>> contacts = contacts_from_pybullet(box, client)
    >>> {tuple((c.normal.round(6) + 0.0).tolist()) for c in contacts}  # out of the box: down
    {(0.0, 0.0, -1.0)}
    >>> {c.mu for c in contacts}   # both lateralFriction are pybullet's default 0.5: 0.5 x 0.5
    {0.25}
    >>> contacts_from_pybullet(box, client, contact_model="soft")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: pybullet: contact_model='soft' but body 1 and body 0 ...
    >>> pb.disconnect(client)
    """
    import pybullet as pb

    where = "pybullet"
    body = one_of(where, "body", "object_id", body, object_id)
    fingers = one_of(where, "fingers", "other_ids", fingers, other_ids)
    model_field = "model" if model is not None else "contact_model"
    contact_model = one_of(where, "contact_model", "model", contact_model, model)
    if body is None:
        raise InputError(f"{where}: give the object's body id ('body')")
    client = _connected(pb, client)
    obj = _body(pb, body, client, "body")
    check_options(where, contact_model, mu, torsion, friction, max_distance, model_field)
    kind: Model = contact_model or "hard"
    keep = None if fingers is None else [_finger(pb, f, client, "fingers") for f in fingers]

    def kept(other: int, other_link: int) -> bool:
        return keep is None or any(b == other and (k is None or k == other_link)
                                   for b, k in keep)

    rows = pb.getContactPoints(bodyA=obj, physicsClientId=client) or ()
    dynamics: dict[tuple[int, int], tuple[float, float]] = {}

    def coefficients(body: int, body_link: int) -> tuple[float, float]:
        if (body, body_link) not in dynamics:
            info = pb.getDynamicsInfo(body, body_link, physicsClientId=client)
            dynamics[body, body_link] = (float(info[1]), float(info[7]))
        return dynamics[body, body_link]

    points, normals, mus, tors = [], [], [], []
    for row in rows:
        body_a, body_b, link_a, link_b = row[1], row[2], row[3], row[4]
        if body_a == body_b:  # the object touching itself
            continue
        on_a = body_a == obj and (link is None or link_a == link)
        on_b = body_b == obj and (link is None or link_b == link)
        if on_a == on_b:  # not on the object's link
            continue
        other, other_link = (body_b, link_b) if on_a else (body_a, link_a)
        if not kept(other, other_link):
            continue
        if row[8] > max_distance:
            continue
        normal_b = np.asarray(row[7], dtype=float)
        points.append(row[5] if on_a else row[6])
        normals.append(-normal_b if on_a else normal_b)
        own = coefficients(obj, link_a if on_a else link_b)
        theirs = coefficients(other, other_link)
        lateral = float(np.clip(own[0] * theirs[0], -MAX_FRICTION, MAX_FRICTION))
        spin = float(np.clip(own[1] * theirs[0] + theirs[1] * own[0],
                             -MAX_FRICTION, MAX_FRICTION))
        if mu is None and lateral < 0:
            raise InputError(f"{where}: body {obj} and body {other} (link {other_link}) "
                             f"combine to a negative friction {lateral:g}")
        if torsion is None and kind == "soft" and spin <= 0:
            raise InputError(
                f"{where}: contact_model='soft' but body {obj} and body {other} (link "
                f"{other_link}) combine to spinning friction {spin:g}: Bullet simulates no "
                "positive torsion there; set spinningFriction (changeDynamics), give "
                "torsion=, or take contact_model='hard'")
        mus.append(lateral if mu is None else float(mu))
        tors.append(spin if torsion is None else float(torsion))
    if not points:
        what = "" if keep is None else " with bodies " + ", ".join(
            str(b) if k is None else f"{b} (link {k})" for b, k in keep)
        on = "" if link is None else f" (link {link})"
        raise InputError(f"{where}: body {obj}{on} has no contacts{what} within distance "
                         f"{max_distance:g} (step the simulation first?)")
    return contacts_from_rows(np.array(points, dtype=float), np.array(normals), np.array(mus),
                              np.array(tors), [kind] * len(points), merge, where)
