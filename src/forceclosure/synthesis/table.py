"""The table of constructions, written out whole: which construction serves which hand.

Every way of building independent regions of contact is one
:class:`~forceclosure.synthesis.construction.Construction` in one module; this
table is the one list of them, read top to bottom, under ``(dimension, fingers,
contact, name)`` (as MuJoCo MJX writes its collision table). ``fingers=None``
and ``contact="any"`` are wildcards: such an entry serves every hand of its
dimension that no entry names exactly — segments grown around sampled grasps on a
polygon, the mesh method in space (Roa & Suárez 2009) — beyond the paper's hands
(Nguyen 1988, §5.2, §5.3, §5.5). A newcomer adds a construction by writing its
module and one line here.

Each entry names its module and the construction's name in it as text, so that
reading the table (the names ``forceclosure synthesize --help`` offers) loads no
construction and no numpy; :func:`constructions` imports them.
:func:`~forceclosure.synthesis.best.synthesize` is the one door to every entry
(``construction=`` a name here, or a :class:`Construction`).

Examples
--------
>>> names()
('maximal', 'nguyen', 'vertices', 'grown', 'mesh')
>>> c = construction_for(2, 2, "hard")
>>> c.name, c.paper, c.method
('maximal', '§5.1, Corollary 3', 'edges')
>>> construction_for(3, 4, "hard").name      # no construction on faces: the mesh method
'mesh'
>>> construction_for(3, 3, "hard", "vertices")
Traceback (most recent call last):
...
forceclosure.errors.InputError: construction='vertices': none for 3 hard fingers on a \
polyhedron; the table has maximal or mesh for them

References
----------
V.-D. Nguyen, "Constructing force-closure grasps", IJRR 7(3), 1988, §5.
M. A. Roa and R. Suárez, "Computation of independent contact regions for grasping 3-D
objects", IEEE T-RO 25(4), 2009.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from importlib import import_module
from typing import TYPE_CHECKING

from ..errors import InputError

if TYPE_CHECKING:
    from .construction import Construction

__all__ = ["DEFAULT", "TABLE", "Entry", "construction_for", "constructions", "names", "served"]


@dataclass(frozen=True)
class Entry:
    """One line of the table: a hand, a name, and where its construction is.

    Attributes
    ----------
    dim : {2, 3}
    fingers : int or None
        ``None``: any number (a wildcard).
    contact : str
        ``"hard"``, ``"soft"``, ``"frictionless"``; ``"any"``: a wildcard.
    name : str
        ``"maximal"``, ``"nguyen"``, ``"vertices"``, ``"mesh"``, ...
    where : str
        ``"module:NAME"``: the construction, in a module under ``forceclosure.synthesis``.
    """

    dim: int
    fingers: int | None
    contact: str
    name: str
    where: str

    @property
    def key(self) -> tuple[int, int | None, str, str]:
        """``(dim, fingers, contact, name)``."""
        return (self.dim, self.fingers, self.contact, self.name)


#: The table: every construction, in the order it is listed and searched for a hand.
TABLE: tuple[Entry, ...] = (
    # polygons, on edges (§5.1, §5.4)
    Entry(2, 2, "hard", "maximal", "planar.two_fingers:MAXIMAL"),
    Entry(2, 2, "hard", "nguyen", "planar.two_sided_cone:NGUYEN"),
    Entry(2, 2, "hard", "vertices", "planar.vertex_grasps:VERTICES"),
    Entry(2, 3, "hard", "maximal", "planar.three_fingers:THREE_FINGERS"),
    Entry(2, 4, "frictionless", "maximal", "planar.four_frictionless:MAXIMAL"),
    Entry(2, 4, "frictionless", "nguyen", "planar.four_frictionless:NGUYEN"),
    Entry(2, 4, "hard", "maximal", "planar.two_pairs:TWO_PAIRS"),
    # any other hand on a polygon: segments grown around sampled prototypes
    Entry(2, None, "any", "grown", "planar.grown_segments:GROWN"),
    # polyhedra, on faces (§5.2, §5.3, §5.5)
    Entry(3, 2, "soft", "maximal", "spatial.two_soft:MAXIMAL"),
    Entry(3, 2, "soft", "nguyen", "spatial.two_soft:NGUYEN"),
    Entry(3, 3, "hard", "maximal", "spatial.three_hard:THREE_HARD"),
    Entry(3, 7, "frictionless", "maximal", "spatial.seven_frictionless:SEVEN"),
    # any other hand in space, and curved objects: regions grown on the mesh
    Entry(3, None, "any", "mesh", "mesh.grown_regions:MESH"),
)

#: The name :func:`construction_for` takes when none is given: the largest regions the table
#: builds for the hand, or its wildcard entry for a hand no entry names.
DEFAULT = "maximal"


def names() -> tuple[str, ...]:
    """The table's construction names, each once, in table order (imports nothing)."""
    return tuple(dict.fromkeys(e.name for e in TABLE))


@cache
def _load(entry: Entry) -> Construction:
    module, _, attribute = entry.where.partition(":")
    construction = getattr(import_module(f"{__package__}.{module}"), attribute)
    if construction.key != entry.key:
        raise RuntimeError(f"the table's {entry.key} names {entry.where}, whose key is "
                           f"{construction.key}")
    return construction


def constructions() -> tuple[Construction, ...]:
    """Every construction of the table, in its order (their modules imported).

    Examples
    --------
    >>> sorted({c.method for c in constructions()})
    ['edges', 'faces', 'mesh']
    """
    return tuple(_load(e) for e in TABLE)


def served(dim: int, fingers: int | None, contact: str) -> tuple[Construction, ...]:
    """The constructions that serve a hand on a ``dim``-D object: the entries that name it,
    then the wildcard entries, each in table order. In the plane a soft finger acts as a
    hard one.

    Examples
    --------
    >>> [c.name for c in served(3, 2, "soft")]
    ['maximal', 'nguyen', 'mesh']
    >>> [c.name for c in served(2, 7, "hard")]
    ['grown']
    """
    if dim == 2 and contact == "soft":
        contact = "hard"
    exact = [c for c in constructions() if (c.dim, c.fingers, c.contact) == (dim, fingers,
                                                                              contact)]
    wild = [c for c in constructions() if c.dim == dim and c not in exact
            and c.fingers in (None, fingers) and c.contact in ("any", contact)]
    return (*exact, *wild)


def _listed(words: list[str]) -> str:
    return ", ".join(words[:-1]) + (" or " if len(words) > 1 else "") + words[-1]


def construction_for(dim: int, fingers: int, contact: str,
                     name: str | Construction = DEFAULT, method: str = "auto",
                     curved: bool = False) -> Construction:
    """The table's construction for a hand on a ``dim``-D object.

    ``name``: an entry's name among those that serve the hand (:func:`served`); the
    default, ``"maximal"``, falls back to the hand's wildcard entry where no entry names
    the hand. A :class:`Construction` is taken as it is, once it is seen to serve the hand.
    On a polyhedron ``method="mesh"`` asks for the mesh method, ``"faces"`` for a
    construction on faces; ``"auto"`` takes the construction unless the object is
    ``curved`` (most of its faces one triangle).

    Raises
    ------
    InputError
        When the name is not the table's for the hand, in one line listing those that are.
    """
    if dim == 2 and contact == "soft":
        contact = "hard"
    shape = "polygon" if dim == 2 else "polyhedron"
    hand = served(dim, fingers, contact)
    if not isinstance(name, str):
        if not (name.dim == dim and name.fingers in (None, fingers)
                and name.contact in ("any", contact)):
            raise InputError(f"construction {name.key}: it does not serve {fingers} {contact} "
                             f"fingers on a {shape}")
        return name
    named = [c for c in hand if c.name == name]
    wild = [c for c in hand if c.fingers is None or c.contact == "any"]
    if not named and not (name == DEFAULT and wild):
        if not hand:
            raise InputError(f"construction={name!r}: no construction serves {fingers} "
                             f"{contact} fingers on a {shape}")
        raise InputError(f"construction={name!r}: none for {fingers} {contact} fingers on a "
                         f"{shape}; the table has "
                         f"{_listed(list(dict.fromkeys(c.name for c in hand)))} for them")
    if dim == 3 and method == "faces" and not (named and named[0].method == "faces"):
        raise InputError(f"method='faces': the paper constructs two soft, three hard or "
                         f"seven frictionless fingers on faces, not {fingers} {contact}; "
                         "use method='mesh'")
    if dim == 3 and (method == "mesh" or (method == "auto" and curved)):
        mesh = [c for c in hand if c.method == "mesh"]
        if mesh:
            return mesh[0]
    return (named or wild)[0]
