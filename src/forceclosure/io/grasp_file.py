"""The grasp file: JSON in, JSON out (schema: ``forceclosure/schemas/grasp-file.schema.json``).

Input holds one grasp or many::

    {"cone": "exact" | {"edges": 8, "fit": "inscribed"},
     "grasps": [{"name": "pinch",
                 "contacts": [{"point": [x, y(, z)], "normal": [...],
                               "model": "frictionless" | "hard" | "soft",
                               "mu": 0.5, "torsion": 0.01}]}]}

``{"contacts": [...]}`` at the top level is a file of one grasp. Beyond the
minimum, a contact may give ``"points"`` (an edge or face contact: the
segment's ends or the face's vertices) instead of ``"point"``, or
``"normals"`` (a vertex contact) instead of ``"normal"``; a grasp may give
``"reference"`` and ``"length_scale"`` for its torque frame.

Each bad grasp is reported with the grasp and contact it concerns, and the
other grasps are still read.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.closure import Analysis, Verdict, analyze_explained
from ..analysis.quality import epsilon, least_friction
from ..contacts import (
    MAX_CONTACTS,
    MAX_QUALITY_CONTACTS,
    MODELS,
    Cone,
    Contact,
    check_grasp,
    make_contact,
    parse_cone,
)
from ..errors import InputError, clip, parse_json, shown

__all__ = ["CONTACT_KEYS", "FILE_KEYS", "GRASP_KEYS", "MAX_COORDINATE", "NOT_COMPUTED",
           "NOT_FINITE", "GraspEntry", "GraspFile", "parse_cone", "parse_contact",
           "parse_grasp_file", "result_record"]

CONTACT_KEYS = {"point", "points", "normal", "normals", "model", "mu", "torsion"}
GRASP_KEYS = {"name", "contacts", "reference", "length_scale"}
FILE_KEYS = {"cone", "grasps", "contacts", "name", "reference", "length_scale", "$schema"}
#: The largest coordinate (of a point, normal or reference) and length scale read: beyond
#: it, products of coordinates overflow (1e308 is the largest float) and no verdict is exact.
MAX_COORDINATE = 1e100


@dataclass(frozen=True, eq=False)
class GraspEntry:
    """One grasp of a file: its contacts, or the error that stopped them."""

    index: int
    name: str | None
    contacts: list[Contact] | None
    reference: list[float] | None
    length_scale: float | None
    error: str | None

    @property
    def label(self) -> str:
        """``grasp 3`` or ``grasp 3 ("pinch")``."""
        return f"grasp {self.index}" + (f' ("{clip(self.name, 80)}")' if self.name else "")


def _number(value: Any, field: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(f"field '{field}' must be a number, got {shown(value)}")
    try:
        number = float(value)
    except OverflowError:  # an integer of hundreds of digits
        raise InputError(f"field '{field}' must be finite, got an integer of "
                         f"{len(str(abs(value))):,} digits") from None
    if math.isnan(number):
        raise InputError(f"field '{field}' must be finite, got NaN")
    if math.isinf(number):
        raise InputError(f"field '{field}' must be finite, got {'-' if number < 0 else ''}"
                         "Infinity or a number beyond the largest float (1.8e308)")
    return number


def _bounded(value: Any, field: str) -> float:
    number = _number(value, field)
    if abs(number) > MAX_COORDINATE:
        raise InputError(f"field '{field}' is too large: {number:g} (at most "
                         f"{MAX_COORDINATE:g} in magnitude; rescale the grasp)")
    return number


def _coords(value: Any, field: str) -> list[float]:
    if not isinstance(value, list) or len(value) not in (2, 3):
        raise InputError(f"field '{field}' must be a list of 2 or 3 numbers, "
                         f"got {shown(value)}")
    return [_bounded(v, field) for v in value]


def _coord_list(value: Any, field: str) -> list[list[float]]:
    if not isinstance(value, list) or not value:
        raise InputError(f"field '{field}' must be a non-empty list of coordinate lists, "
                         f"got {shown(value)}")
    return [_coords(v, field) for v in value]


def parse_contact(data: Any) -> Contact:
    """One contact object of the file format, validated."""
    if not isinstance(data, dict):
        raise InputError(f"must be an object, got {shown(data)}")
    unknown = set(data) - CONTACT_KEYS
    if unknown:
        raise InputError(f"unknown field '{clip(sorted(unknown)[0], 80)}'")
    for a, b in (("point", "points"), ("normal", "normals")):
        if (a in data) == (b in data):
            raise InputError(f"give exactly one of '{a}' and '{b}'")
    model = data.get("model", "hard")
    if model not in MODELS:
        raise InputError(f"field 'model' must be one of {', '.join(MODELS)}, "
                         f"got {shown(model)}")
    mu = _number(data.get("mu", 0.0), "mu")
    torsion = data.get("torsion")
    torsion = None if torsion is None else _number(torsion, "torsion")
    if mu < 0:
        raise InputError(f"field 'mu' must be >= 0, got {mu:g}")
    if torsion is not None and torsion < 0:
        raise InputError(f"field 'torsion' must be >= 0, got {torsion:g}")
    points = ([_coords(data["point"], "point")] if "point" in data
              else _coord_list(data["points"], "points"))
    normals = ([_coords(data["normal"], "normal")] if "normal" in data
               else _coord_list(data["normals"], "normals"))
    return make_contact(points, normals, model, mu, torsion,
                 "point" if "point" in data else "points",
                 "normal" if "normal" in data else "normals")


def _parse_grasp(index: int, data: Any) -> GraspEntry:
    name = data.get("name") if isinstance(data, dict) else None
    name = name if isinstance(name, str) else None
    try:
        if not isinstance(data, dict):
            raise InputError(f"must be an object with 'contacts', got {shown(data, 60)}")
        unknown = set(data) - GRASP_KEYS
        if unknown:
            raise InputError(f"unknown field '{clip(sorted(unknown)[0], 80)}'")
        if "contacts" not in data:
            raise InputError("missing field 'contacts'")
        if not isinstance(data["contacts"], list) or not data["contacts"]:
            raise InputError("field 'contacts' must be a non-empty list")
        if len(data["contacts"]) > MAX_CONTACTS:  # before reading them
            raise InputError(f"{len(data['contacts']):,} contacts; at most {MAX_CONTACTS:,} "
                             "are analysed")
        contacts = []
        for j, c in enumerate(data["contacts"], start=1):
            try:
                contacts.append(parse_contact(c))
            except InputError as e:
                raise e.within(f"contact {j}") from None
        check_grasp(contacts)
        reference = data.get("reference")
        reference = None if reference is None else _coords(reference, "reference")
        scale = data.get("length_scale")
        scale = None if scale is None else _bounded(scale, "length_scale")
        if scale is not None and scale <= 0:
            raise InputError(f"field 'length_scale' must be > 0, got {scale:g}")
        if reference is not None and len(reference) != contacts[0].dim:
            raise InputError(f"field 'reference' has {len(reference)} coordinates; the "
                             f"contacts have {contacts[0].dim}")
        return GraspEntry(index, name, contacts, reference, scale, None)
    except InputError as e:
        entry = GraspEntry(index, name, None, None, None, None)
        return GraspEntry(index, name, None, None, None, str(e.within(entry.label)))


@dataclass(frozen=True, eq=False)
class GraspFile:
    """A parsed grasp file: the cone option and its grasps, good and bad."""

    cone: str | Cone
    grasps: list[GraspEntry]


def parse_grasp_file(text: str, source: str = "input") -> GraspFile:
    """Parse and validate the grasp file format.

    Raises :class:`InputError` for a file that cannot be read as a whole
    (malformed JSON, no grasps); a bad grasp becomes an entry with ``error``.

    Examples
    --------
    >>> f = parse_grasp_file('{"contacts": [{"point": [0, 1], "normal": [0, 0]}]}')
    >>> f.grasps[0].error
    "grasp 1: contact 1: field 'normal' is a zero vector; a normal needs a direction"
    """
    data = parse_json(text, source)
    if not isinstance(data, dict):
        raise InputError(f"{source}: the top level must be an object with 'grasps' or "
                         "'contacts'")
    unknown = set(data) - FILE_KEYS
    if unknown:
        raise InputError(f"{source}: unknown field '{clip(sorted(unknown)[0], 80)}'")
    try:
        cone = parse_cone(data.get("cone", "exact"))
    except InputError as e:
        raise e.within(source) from None
    if "grasps" in data:
        if "contacts" in data:
            raise InputError(f"{source}: give 'grasps' or 'contacts' at the top level, not both")
        if not isinstance(data["grasps"], list) or not data["grasps"]:
            raise InputError(f"{source}: field 'grasps' must be a non-empty list")
        grasps = [_parse_grasp(i, g) for i, g in enumerate(data["grasps"], start=1)]
    elif "contacts" in data:
        single = {k: v for k, v in data.items() if k in GRASP_KEYS}
        grasps = [_parse_grasp(1, single)]
    else:
        raise InputError(f"{source}: missing field 'grasps' (or 'contacts' for one grasp)")
    return GraspFile(cone, grasps)


def _num(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def _finite(value: Any) -> bool:
    """No NaN or infinity anywhere in a number or nested list of numbers."""
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, list | tuple):
        return all(_finite(v) for v in value)
    return True


#: Why a value is null in a record, when not for its usual reason (``null_reasons``).
NOT_COMPUTED = "not computed (--no-quality)"
NOT_FINITE = "not a finite number (the computation overflowed)"
UNRESOLVED = ("not resolved: the grasp is closed, so it is positive, but doubles do not "
              "resolve its wrench hull (torques and forces too far apart at this length scale)")
UNRESOLVED_MARGIN = ("not resolved at this length scale (the verdict was proved in the "
                     "grasp's own frame: its margin there is in 'reason')")
TOO_MANY = (f"not computed: more than {MAX_QUALITY_CONTACTS} spatial contact points "
            "(minutes a grasp beyond)")


def _analyse(entry: GraspEntry, contacts: list[Contact], cone: str | Cone, quality: bool,
             ) -> tuple[Analysis, float | None, float | None]:
    a = analyze_explained(contacts, cone=cone, reference=entry.reference,
                          length_scale=entry.length_scale)
    eps = mu_star = None
    if quality:
        if a.verdict is Verdict.CLOSURE:
            eps = epsilon(contacts, reference=entry.reference,
                          length_scale=entry.length_scale).value
        mu_star = least_friction(contacts, cone=cone)
    return a, eps, mu_star


def result_record(entry: GraspEntry, cone: str | Cone, quality: bool = True,
                  ) -> tuple[dict[str, Any], Analysis | None]:
    """The ``--json`` record of one grasp (keys in docs/analysis.md), and its analysis.

    A grasp that cannot be analysed gets ``{"name", "error"}`` (the error
    names the grasp) and no analysis. No value is NaN or infinite: such a
    value is ``null``, and ``null_reasons`` says why, as it does for the
    quality left out with ``quality=False``.

    Examples
    --------
    >>> f = parse_grasp_file('{"contacts": [{"point": [-1, 0], "normal": [-1, 0], "mu": 0.3},'
    ...                      '{"point": [1, 0], "normal": [1, 0], "mu": 0.3}]}')
    >>> record, _ = result_record(f.grasps[0], f.cone, quality=False)
    >>> record["verdict"], record["least_friction"], record["null_reasons"]["least_friction"]
    ('closure', None, 'not computed (--no-quality)')
    """
    contacts = entry.contacts
    if entry.error is not None or contacts is None:  # a grasp has its contacts or its error
        return {"name": entry.name, "error": entry.error}, None
    too_many = contacts[0].dim == 3 and sum(
        len(c.points) for c in contacts) > MAX_QUALITY_CONTACTS
    try:
        a, eps, mu_star = _analyse(entry, contacts, cone, quality and not too_many)
    except InputError as e:
        return {"name": entry.name, "error": str(e.within(entry.label))}, None
    closed = a.verdict is Verdict.CLOSURE
    record = {
        "name": entry.name,
        "verdict": a.verdict.value,
        "force_closure": closed,
        "rank": a.rank,
        "margin": _num(a.margin),
        "force_direction_closure": a.force_direction_closure,
        "torque_closure": a.torque_closure,
        "unresisted_twist": None if a.twist is None else np.round(a.twist, 12).tolist(),
        "unresisted_motion": None if a.motion is None else a.motion.describe(),
        "epsilon": _num(eps),
        "least_friction": None if mu_star is None else _num(mu_star),
        "reason": a.reason,
        "cone": a.cone,
        "reference": a.reference.tolist(),
        "length_scale": a.length_scale,
        "contact_forces": None if a.contact_forces is None else a.contact_forces.tolist(),
    }
    reasons = {key: NOT_FINITE for key, value in record.items() if not _finite(value)}
    reasons.update({key: NOT_FINITE for key, value in (("margin", a.margin), ("epsilon", eps))
                    if value is not None and not math.isfinite(value)})  # least friction:
    # infinite when no friction closes the grasp, its usual null
    if closed and eps is not None and not eps > 0:  # Theorem 1: a closed grasp's is > 0
        reasons["epsilon"] = UNRESOLVED
    if closed and a.margin is None:  # proved in the grasp's own frame (its reason says so)
        reasons["margin"] = UNRESOLVED_MARGIN
    if not quality:
        reasons.update(epsilon=NOT_COMPUTED, least_friction=NOT_COMPUTED)
    elif too_many:
        reasons.update(epsilon=TOO_MANY, least_friction=TOO_MANY)
    for key in reasons:
        record[key] = None
    if reasons:
        record["null_reasons"] = reasons
    return record, a
