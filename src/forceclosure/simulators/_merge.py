"""Point contacts read from a simulator, merged when a contact manifold repeats one; and
the options both adapters share, checked alike.

Both adapters turn each simulator contact into one row: the point on the
object's surface, the object's outward normal there, and its friction and
torsional coefficients. Simulators can report the same contact twice (two
manifolds of a compound shape meeting at one point, a contact cached from the
previous step next to its refreshed copy); :func:`contacts_from_rows` keeps one
of each such pair, since a repeated generator adds nothing to a wrench cone.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Literal, TypeVar

import numpy as np
from numpy.typing import NDArray

from ..contacts import MODELS, Contact, Model, point_contact
from ..errors import InputError

__all__ = ["FRICTIONS", "MERGE", "Friction", "check_options", "contacts_from_rows",
           "one_of"]

#: How the simulator's friction coefficients are read: as reported, or scaled so that the
#: analysed circular cone lies inside the cone the simulator simulates.
FRICTIONS = ("nominal", "inner")
Friction = Literal["nominal", "inner"]

#: Default distance (in the scene's length unit) within which two reported points with the
#: same normal are one contact; normals are "the same" within ``MERGE`` radians.
MERGE = 1e-6


T = TypeVar("T")


def one_of(where: str, new: str, old: str, new_value: T | None, old_value: T | None) -> T | None:
    """The value of an option given by its common name ``new`` or its older name ``old``
    (both still accepted); refused in one line when both are given.

    Examples
    --------
    >>> one_of("pybullet", "contact_model", "model", None, "soft")
    'soft'
    """
    if new_value is not None and old_value is not None:
        raise InputError(f"{where}: give '{new}' or its older name '{old}', not both")
    return new_value if new_value is not None else old_value


def check_options(where: str, contact_model: object, mu: object, torsion: object,
                  friction: object, max_distance: object,
                  model_field: str = "contact_model") -> None:
    """Refuse, in one line naming the parameter, an option both adapters take
    (``model_field``: the name the contact model was given by).

    Examples
    --------
    >>> check_options("mujoco", "soft", 0.5, None, "inner", 0.0)   # all fine: nothing said
    >>> check_options("mujoco", "soft", -1, None, "nominal", 0.0)
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: mujoco: 'mu' must be a finite number >= 0, got -1
    """
    if contact_model is not None and contact_model not in MODELS:
        raise InputError(f"{where}: '{model_field}' must be one of {', '.join(MODELS)}; "
                         f"got {contact_model!r}")
    if friction not in FRICTIONS:
        raise InputError(f"{where}: 'friction' must be 'nominal' or 'inner', got {friction!r}")
    for name, value in (("mu", mu), ("torsion", torsion), ("max_distance", max_distance)):
        if value is not None and (not isinstance(value, int | float) or isinstance(value, bool)
                                  or not math.isfinite(value)
                                  or (name != "max_distance" and value < 0)):
            raise InputError(f"{where}: '{name}' must be a finite number"
                             f"{'' if name == 'max_distance' else ' >= 0'}, got {value!r}")


def contacts_from_rows(points: NDArray[np.float64], normals: NDArray[np.float64],
                       mu: NDArray[np.float64], torsion: NDArray[np.float64] | None,
                       models: Sequence[Model], merge: float, where: str) -> list[Contact]:
    """Point contacts from ``(k, 3)`` rows, repeated rows (within ``merge``) kept once.

    ``models`` gives each row's contact model; ``torsion`` (or None) each
    soft row's torsional coefficient. Two rows are one contact when they have
    the same model, their points are within ``merge`` of each other and their
    normals within ``merge`` radians; the kept row takes the
    smaller friction and torsion of the two (the smaller cone, so a verdict of
    closure never rests on the repeated row). ``merge=0`` keeps exact repeats
    only once and every other row.

    Examples
    --------
    >>> rows = np.array([[0.0, 0, 0], [0, 0, 1e-9], [1, 0, 0]])
    >>> up = np.array([[0.0, 0, 1]] * 3)
    >>> cs = contacts_from_rows(rows, up, np.array([0.5, 0.4, 0.5]), None, ["hard"] * 3,
    ...                         1e-6, "x")
    >>> len(cs), cs[0].mu
    (2, 0.4)
    """
    if not isinstance(merge, int | float) or isinstance(merge, bool) or not (
            math.isfinite(merge) and merge >= 0):
        raise InputError(f"{where}: 'merge' must be a finite distance >= 0, got {merge!r}")
    keep: list[int] = []
    mu = mu.astype(float).copy()
    tors = None if torsion is None else torsion.astype(float).copy()
    for i in range(points.shape[0]):
        for j in keep:
            if models[i] != models[j] or np.linalg.norm(points[i] - points[j]) > merge:
                continue
            if math.acos(float(np.clip(normals[i] @ normals[j], -1.0, 1.0))) <= merge:
                mu[j] = min(mu[j], mu[i])
                if tors is not None:
                    tors[j] = min(tors[j], tors[i])
                break
        else:
            keep.append(i)
    return [point_contact(points[i], normals[i], models[i], float(mu[i]),
                          None if tors is None or models[i] != "soft" else float(tors[i]))
            for i in keep]
