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
Rolling friction is not represented.

Bullet keeps at most four points per pair of shapes, not always the whole
contact face (a box dropped exactly flat on a ``GEOM_PLANE`` had two, on
``plane.urdf`` four); the adapter reports what Bullet has, each repeated
point once (see :func:`forceclosure.simulators._merge.contacts_from_rows`).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from ..contacts import MODELS, Contact, Model
from ..errors import InputError
from ._merge import MERGE, contacts_from_rows

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


def contacts_from_pybullet(object_id: int, client: int = 0, *,
                           other_ids: Iterable[int] | None = None, link: int | None = None,
                           model: Model = "hard", mu: float | None = None,
                           torsion: float | None = None, max_distance: float = 0.0,
                           merge: float = MERGE) -> list[Contact]:
    """The contacts on body ``object_id`` in pybullet client ``client``.

    Read after ``stepSimulation`` (or ``performCollisionDetection``): each
    manifold point touching the object becomes a point contact at the point
    on the object's surface, with the object's outward normal there (see the
    module's notes for the sign of ``contactNormalOnB``).

    Parameters
    ----------
    object_id : int
        The body being grasped.
    client : int
        The physics client (``pybullet.connect``'s result); 0 by default.
    other_ids : iterable of int, optional
        Keep only contacts with these bodies (the fingers, say, not the table).
    link : int, optional
        Keep only contacts on this link of the object (-1: its base).
    model : {"hard", "soft", "frictionless"}
        The contact model of every contact.
    mu, torsion : float, optional
        Override Bullet's combined friction and (soft fingers) combined
        spinning friction for every contact.
    max_distance : float
        Points farther apart than this (``contactDistance``, negative when
        penetrating) are not touching and are left out.
    merge : float
        Points within ``merge`` of each other, with normals within ``merge``
        radians, are one contact (kept once, with the smaller coefficients).

    Returns
    -------
    list of Contact
        Ready for :func:`forceclosure.analyze`.

    Raises
    ------
    InputError
        The client is not connected, a body id is unknown, or the object has
        no contact left after the filters (one line each).

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
    >>> pb.disconnect(client)
    """
    import pybullet as pb

    where = "pybullet"
    client = _connected(pb, client)
    obj = _body(pb, object_id, client, "object_id")
    others = None if other_ids is None else {_body(pb, b, client, "other_ids")
                                             for b in other_ids}
    if model not in MODELS:
        raise InputError(f"{where}: 'model' must be one of {', '.join(MODELS)}; got {model!r}")
    for name, value in (("mu", mu), ("torsion", torsion), ("max_distance", max_distance)):
        if value is not None and (not isinstance(value, int | float) or isinstance(value, bool)
                                  or not np.isfinite(value)
                                  or (name != "max_distance" and value < 0)):
            raise InputError(f"{where}: '{name}' must be a finite number"
                             f"{'' if name == 'max_distance' else ' >= 0'}, got {value!r}")
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
        if others is not None and other not in others:
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
        if torsion is None and model == "soft" and spin < 0:
            raise InputError(f"{where}: body {obj} and body {other} (link {other_link}) "
                             f"combine to a negative spinning friction {spin:g}")
        mus.append(lateral if mu is None else float(mu))
        tors.append(spin if torsion is None else float(torsion))
    if not points:
        what = "" if others is None else f" with bodies {sorted(others)}"
        on = "" if link is None else f" (link {link})"
        raise InputError(f"{where}: body {obj}{on} has no contacts{what} within distance "
                         f"{max_distance:g} (step the simulation first?)")
    return contacts_from_rows(np.array(points, dtype=float), np.array(normals), np.array(mus),
                              np.array(tors), [model] * len(points), merge, where)
