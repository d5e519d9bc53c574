"""Contacts of a body or geom in a MuJoCo scene, as forceclosure contacts.

Each ``mjContact`` in ``data.contact[:data.ncon]`` joins geoms ``geom[0]`` and
``geom[1]``; ``frame[0:3]`` is the contact normal, pointing **from geom[0] to
geom[1]``; ``pos`` is the midpoint between the two surfaces and ``dist`` their
signed distance along the normal (negative: penetration) — ``mjContact`` in
MuJoCo's ``include/mujoco/mjdata.h``. So geom[0]'s surface point is
``pos - dist/2 · normal`` with outward normal ``normal``, and geom[1]'s is
``pos + dist/2 · normal`` with outward normal ``-normal``.

Friction is the contact's own ``friction`` (tangent1, tangent2, spin, roll1,
roll2), which MuJoCo has already combined from the two geoms (the
element-wise maximum, unless one geom has the higher ``priority`` or an
explicit ``<pair>`` sets it: "Contact parameters" in MuJoCo's modeling
chapter). ``dim`` (the contact's condim) says which of them act: 1 none
(frictionless), 3 sliding (hard finger), 4 and 6 sliding and spin (soft
finger; rolling is not represented). The torsional coefficient
``friction[2]`` is a length (the spin torque is at most it times the normal
force), as :class:`forceclosure.Contact`'s ``torsion`` is.

The circular cone with these coefficients is not exactly MuJoCo's cone:
MuJoCo's default *pyramidal* cone has the ``2 (dim - 1)`` edges
``n ± mu_i e_i`` (it lies inside the circular one, the spin direction
trading against sliding), its *elliptic* cone couples sliding and spin,
``(f_t / mu)^2 + (tau / gamma)^2 <= f_n^2``. ``friction="inner"`` scales the
coefficients so that the analysed cone lies inside MuJoCo's (pyramidal:
``mu / sqrt 2`` for hard fingers, ``mu / (2 sqrt 2)`` and ``gamma / 2`` for
soft; elliptic: ``mu`` for hard, ``mu / sqrt 2`` and ``gamma / sqrt 2`` for
soft): a verdict of closure then holds for the cone MuJoCo simulates.

A soft finger forced on a contact (``contact_model="soft"``) whose torsional coefficient
comes out 0 (condim 1 or 3, or ``friction[2]`` 0) would be a hard finger under another
name: it is refused in one line unless ``torsion=`` is given. A contact whose own condim
(4 or 6) makes it soft keeps MuJoCo's coefficient, whatever it is.

Points (``pos``) and normals (``frame``) are in the world frame, not the body's: analyse
them as they are, or move them into the body's frame with ``data.xpos`` and
``data.xmat`` first.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from ..contacts import Contact, Model
from ..errors import InputError
from ._merge import MERGE, Friction, check_options, contacts_from_rows

__all__ = ["contacts_from_mujoco"]


def _element(mj: Any, model: Any, value: object, kind: str, field: str | None = None) -> int:
    """The id of body or geom ``value`` (an id or a name), or a one-line error."""
    obj = mj.mjtObj.mjOBJ_BODY if kind == "body" else mj.mjtObj.mjOBJ_GEOM
    count = model.nbody if kind == "body" else model.ngeom
    field = field or kind
    if isinstance(value, str):
        found = mj.mj_name2id(model, obj, value)
        if found < 0:
            raise InputError(f"mujoco: no {kind} named {value!r} in the model"
                             + ("" if field == kind else f" ('{field}')"))
        return int(found)
    if not isinstance(value, int | np.integer) or isinstance(value, bool):
        raise InputError(f"mujoco: '{field}' must be an id or a name, got {value!r}")
    if not 0 <= int(value) < count:
        raise InputError(f"mujoco: no {kind} with id {value} (the model has {count})")
    return int(value)


def _model_of(dim: int) -> Model:
    return "frictionless" if dim == 1 else "hard" if dim == 3 else "soft"


def contacts_from_mujoco(model: Any, data: Any, *, body: int | str | None = None,
                         geom: int | str | None = None,
                         fingers: Iterable[int | str] | None = None,
                         finger_geoms: Iterable[int | str] | None = None,
                         contact_model: Model | None = None,
                         mu: float | None = None, torsion: float | None = None,
                         friction: Friction = "nominal", max_distance: float = 0.0,
                         merge: float = MERGE) -> list[Contact]:
    """The contacts on a body (all its geoms) or on one geom of a MuJoCo scene, in the
    world frame.

    Read after ``mj_step`` or ``mj_forward`` (which run collision detection).
    The keyword options are those of :func:`contacts_from_pybullet`, by the
    same names: ``body``, ``fingers``, ``contact_model``, ``mu``,
    ``torsion``, ``friction``, ``max_distance``, ``merge``.

    Parameters
    ----------
    model, data : mujoco.MjModel, mujoco.MjData
        The scene.
    body, geom : int or str
        The object: a body (id or name) or a single geom; give exactly one.
    fingers, finger_geoms : iterable of int or str, optional
        Keep only contacts with these bodies (every geom of each) and these
        geoms (ids or names): the fingers, say, not the table. Either or
        both; without them every contact of the object is kept.
    contact_model : {"frictionless", "hard", "soft"}, optional
        Every contact's model; by default each contact's ``dim`` decides
        (1 frictionless, 3 hard, 4 or 6 soft). ``"soft"`` on a contact with
        no torsional friction (condim 1 or 3, or ``friction[2]`` 0) is
        refused unless ``torsion`` is given.
    mu, torsion : float, optional
        Override the contact's sliding (``min(friction[0], friction[1])``) and
        torsional (``friction[2]``) coefficients. Without an override, the
        coefficients a contact's ``dim`` does not use are 0.
    friction : {"nominal", "inner"}
        ``"nominal"``: the coefficients as MuJoCo reports them; ``"inner"``:
        scaled so the analysed cone lies inside the cone MuJoCo simulates
        (see the module's notes).
    max_distance : float
        Contacts whose ``dist`` exceeds this are not touching and are left out.
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
        No or both of ``body`` and ``geom``, an unknown body or geom, a bad
        option, a soft finger forced where MuJoCo has no torsional friction,
        or no contact left after the filters (one line each).

    References
    ----------
    .. [1] E. Todorov, T. Erez and Y. Tassa, "MuJoCo: A physics engine for model-based
       control", *Proc. IEEE/RSJ IROS*, 2012

    Examples
    --------
    >>> import mujoco
    >>> m = mujoco.MjModel.from_xml_string('''<mujoco><worldbody>
    ...   <geom type="plane" size="1 1 .1" friction="0.8 0.01 0"/>
    ...   <body name="box" pos="0 0 .1"><freejoint/>
    ...     <geom type="box" size=".1 .1 .1" friction="0.5 0.02 0" condim="4"/></body>
    ... </worldbody></mujoco>''')
    >>> d = mujoco.MjData(m)
    >>> for _ in range(100):
    ...     mujoco.mj_step(m, d)
    >>> contacts = contacts_from_mujoco(m, d, body="box")
    >>> len(contacts), contacts[0].normal.tolist(), contacts[0].mu, contacts[0].torsion
    (4, [0.0, 0.0, -1.0], 0.8, 0.02)
    """
    import mujoco as mj

    where = "mujoco"
    if (body is None) == (geom is None):
        raise InputError(f"{where}: give exactly one of 'body' and 'geom'")
    if body is not None:
        ident = _element(mj, model, body, "body")
        mine = np.flatnonzero(np.asarray(model.geom_bodyid) == ident)
        what = f"body {body!r}"
    else:
        ident = _element(mj, model, geom, "geom")
        mine = np.array([ident])
        what = f"geom {geom!r}"
    check_options(where, contact_model, mu, torsion, friction, max_distance)
    theirs = None
    fingers = None if fingers is None else list(fingers)
    finger_geoms = None if finger_geoms is None else list(finger_geoms)
    if fingers is not None or finger_geoms is not None:
        bodies = [_element(mj, model, b, "body", "fingers") for b in (fingers or ())]
        geoms = [_element(mj, model, g, "geom", "finger_geoms") for g in (finger_geoms or ())]
        theirs = np.union1d(np.flatnonzero(np.isin(np.asarray(model.geom_bodyid), bodies)),
                            np.array(geoms, dtype=int))
    ncon = int(data.ncon)
    con = data.contact
    pairs = (np.asarray(con.geom, dtype=int).reshape(ncon, 2) if hasattr(con, "geom")
             else np.stack([np.asarray(con.geom1), np.asarray(con.geom2)], axis=1))
    first, second = np.isin(pairs[:, 0], mine), np.isin(pairs[:, 1], mine)
    dist = np.asarray(con.dist, dtype=float).reshape(ncon)
    wanted = (first != second) & (dist <= max_distance)
    if theirs is not None:  # the other geom of the contact is a finger's
        wanted &= np.isin(np.where(first, pairs[:, 1], pairs[:, 0]), theirs)
    rows = np.flatnonzero(wanted)
    if rows.size == 0:
        named = [f"bodies {list(fingers)}"] if fingers is not None else []
        named += [f"geoms {list(finger_geoms)}"] if finger_geoms is not None else []
        with_ = f" with {' and '.join(named)}" if named else ""
        raise InputError(f"{where}: {what} has no contacts{with_} within distance "
                         f"{max_distance:g} (run mj_forward or mj_step first?)")
    normal = np.asarray(con.frame, dtype=float).reshape(ncon, 9)[rows, :3]
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    pos = np.asarray(con.pos, dtype=float).reshape(ncon, 3)[rows]
    half = (dist[rows] / 2)[:, None]
    sign = np.where(first[rows], 1.0, -1.0)[:, None]   # geom[0]: +normal; geom[1]: -normal
    points = pos - sign * half * normal
    normals = sign * normal
    coef = np.asarray(con.friction, dtype=float).reshape(ncon, 5)[rows]
    dims = np.asarray(con.dim, dtype=int).reshape(ncon)[rows]
    models: list[Model] = [contact_model or _model_of(int(k)) for k in dims]
    slide = np.where(dims >= 3, np.minimum(coef[:, 0], coef[:, 1]), 0.0)
    spin = np.where(dims >= 4, coef[:, 2], 0.0)
    if friction == "inner":
        elliptic = int(model.opt.cone) == int(mj.mjtCone.mjCONE_ELLIPTIC)
        soft = np.array([m == "soft" for m in models])
        if elliptic:
            scale_mu = np.where(soft, 1 / math.sqrt(2), 1.0)
            scale_spin = np.full(len(models), 1 / math.sqrt(2))
        else:
            scale_mu = np.where(soft, 1 / (2 * math.sqrt(2)), 1 / math.sqrt(2))
            scale_spin = np.full(len(models), 0.5)
        slide, spin = slide * scale_mu, spin * scale_spin
    if contact_model == "soft" and torsion is None and np.any(spin <= 0):
        i = int(np.flatnonzero(spin <= 0)[0])
        raise InputError(f"{where}: contact_model='soft' but the contact of geoms "
                         f"{pairs[rows[i], 0]} and {pairs[rows[i], 1]} has no torsional "
                         f"friction in MuJoCo (condim {dims[i]}, friction[2] "
                         f"{coef[i, 2]:g}); give torsion=, a condim of 4 or 6 with "
                         "friction[2] > 0, or another contact_model")
    mus = slide if mu is None else np.full(len(models), float(mu))
    tors = spin if torsion is None else np.full(len(models), float(torsion))
    return contacts_from_rows(points, normals, mus, tors, models, merge, where)
