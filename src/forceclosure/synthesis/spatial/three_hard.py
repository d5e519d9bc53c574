"""Three hard fingers on faces of a polyhedron (Nguyen 1988, §5.3).

**Classification.** Two friction cones ``C_i`` (around ``-n_i``) and ``C_j``
*counter-overlap* when ``C_i ∩ -C_j`` has an interior: the angle between
``-n_i`` and ``n_j`` is below ``alpha_i + alpha_j``. Then the two fingers can
squeeze against each other along the segment between them. The paper sorts
three-finger grasps into four classes by how many of the three pairs
counter-overlap (Fig. 9): none (three fingers around a ball), one (a pinch
plus a finger that stops the spin about the pinch axis), two (the middle
finger is a pivot), and three, in which any finger may leave while the other
two hold on.

**The fourth class needs mu > tan 30°.** With equal friction ``alpha``,
three counter-overlapping pairs need ``angle(n_i, n_j) > 180° - 2 alpha``
for all three pairs. Three unit vectors cannot be pairwise more than 120°
apart: ``|n1 + n2 + n3|^2 >= 0`` gives ``sum n_i . n_j >= -3/2``, while each
term below ``cos 120° = -1/2`` makes the sum less. So ``180° - 2 alpha <
120°``, ``alpha > 30°``.

**Regions.** The force-closure condition for three hard fingers is not
linear in the contacts (it couples the cones through the torques), so the
regions come from the search zones of a prototype grasp on the three faces
(:mod:`.zones`), found by sampling and kept on the faces' convex pieces.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ...analysis.closure import Verdict, vector_closure
from ...errors import InputError
from ...geometry import cones
from ...objects.polyhedron import Polyhedron
from ..construction import Construction, Hand
from ..ranked_search import SPACINGS, ranked
from ..regions import MARGIN, check_margin, narrowed, tie_rounded
from .two_soft import check_faces, check_mu_margin
from .zones import (
    EDGES,
    Prototype,
    ZoneRegions,
    best_prototypes,
    prototype_grasps,
    prototype_samples,
    zone_regions,
)

__all__ = ["CLASSES", "GraspClass", "ThreeHardRegions", "classify_three", "counter_overlap",
           "force_direction_closure_of_faces", "three_hard_construction", "three_hard_regions"]

#: The paper's names for the four classes (Fig. 9), by number of counter-overlapping pairs.
CLASSES = {
    0: "no counter-overlapping pair: the three cones together hold the object",
    1: "one counter-overlapping pair: a pinch, and a finger that stops the spin about it",
    2: "two counter-overlapping pairs: the shared finger is a pivot",
    3: "three counter-overlapping pairs: any finger may leave, the other two hold",
}


@dataclass(frozen=True)
class GraspClass:
    """Nguyen's class of a three-finger grasp (§5.3, Fig. 9).

    Attributes
    ----------
    pairs : tuple of (int, int)
        The finger pairs whose friction cones counter-overlap.
    number : int
        The class, 1 to 4 (one more than the number of pairs).
    description : str
    """

    pairs: tuple[tuple[int, int], ...]
    number: int
    description: str


def counter_overlap(n_i: ArrayLike, n_j: ArrayLike, mu_i: float, mu_j: float | None = None
                    ) -> bool:
    """Whether the friction cones at two contacts counter-overlap (``C_i ∩ -C_j`` has an
    interior): the angle between ``-n_i`` and ``n_j`` is below ``alpha_i + alpha_j``.
    :func:`forceclosure.geometry.cones.counter_overlap` for one pair, as a bool.

    Examples
    --------
    >>> counter_overlap([0, 0, 1], [0, 0, -1], 0.1)   # opposite faces
    True
    >>> counter_overlap([0, 0, 1], [1, 0, 0], 0.9)    # at right angles: needs mu > 1
    False
    """
    return bool(cones.counter_overlap(n_i, n_j, mu_i, mu_j))


def classify_three(normals: ArrayLike, mu: float) -> GraspClass:
    """Nguyen's class (1 to 4) of a grasp by three hard fingers with these outward normals.

    Examples
    --------
    >>> up, down = [0, 0, 1], [0, 0, -1]
    >>> classify_three([up, down, [1, 0, 0]], 0.5).number   # pinch plus a side finger
    2
    >>> classify_three([up, down, down], 0.5).number        # two fingers on one face
    3
    >>> t = np.radians([90, 210, 330])
    >>> ring = np.column_stack([np.cos(t), np.sin(t), np.zeros(3)])  # three around a prism
    >>> classify_three(ring, 0.57).number, classify_three(ring, 0.58).number  # tan 30° = 0.577
    (1, 4)
    """
    N = np.asarray(normals, dtype=float)
    if N.shape != (3, 3):
        raise InputError(f"three fingers need three normals (3, 3), got shape {N.shape}")
    pairs = tuple((i, j) for i, j in itertools.combinations(range(3), 2)
                  if counter_overlap(N[i], N[j], mu))
    return GraspClass(pairs, len(pairs) + 1, CLASSES[len(pairs)])


@dataclass(frozen=True, eq=False)
class ThreeHardRegions(ZoneRegions):
    """Independent regions for three hard fingers on faces, with the grasp's class."""

    @property
    def grasp_class(self) -> GraspClass:
        """Nguyen's class of every grasp in the regions (the faces fix the normals)."""
        normals = [self.polyhedron.faces[r[0].face].normal for r in self.regions]
        return classify_three(normals, self.mu)

    def notes(self) -> list[str]:
        return [f"class {self.grasp_class.number}"]

    def to_dict(self) -> dict[str, object]:
        record = super().to_dict()
        c = self.grasp_class
        record["class"] = {"number": c.number, "pairs": [list(p) for p in c.pairs],
                           "description": c.description}
        return record


def force_direction_closure_of_faces(normals: ArrayLike, mu: float, edges: int = EDGES) -> bool:
    """Theorem 2 for hard fingers on faces: do the friction pyramids together push the
    object in every direction? Depends on the normals only (inscribed pyramids,
    :func:`forceclosure.geometry.cones.friction_forces`)."""
    F = cones.friction_forces(np.asarray(normals, dtype=float), mu, edges)
    return vector_closure(F.reshape(-1, 3).T).verdict is Verdict.CLOSURE


def three_hard_regions(polyhedron: Polyhedron, faces: tuple[int, int, int], mu: float,
                       samples: int = 2000, seed: int = 0,
                       margin: float = MARGIN) -> ThreeHardRegions | None:
    """Independent regions for three hard fingers on three faces (§5.3), or None.

    A prototype grasp on the faces is found by sampling (the one with the
    largest epsilon); its search zones cut each face's convex piece around
    the prototype contact. Two fingers may share a face. Every friction cone
    is narrowed by ``margin`` radians, in the prototype, the construction and
    the proof (:func:`~forceclosure.synthesis.regions.check_margin`).

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> cube = bundled("cube")   # faces 0 (top) and 1 (bottom)
    >>> r = three_hard_regions(cube, (0, 1, 1), 0.5)
    >>> r.certify().holds, r.grasp_class.number
    (True, 3)
    """
    faces = check_faces(polyhedron, faces, 3)
    check_mu_margin(mu, 0.0)
    normals = [polyhedron.faces[f].normal for f in faces]
    if not force_direction_closure_of_faces(normals, mu):
        return None
    found = prototype_grasps(polyhedron, 3, "hard", narrowed(mu, check_margin(margin)),
                             samples=samples, seed=seed, faces=faces)
    if not found:
        return None
    return _around(polyhedron, found[0], mu, margin)


def _around(polyhedron: Polyhedron, prototype: Prototype, mu: float,
            margin: float, resolution: float = 0.0) -> ThreeHardRegions:
    regions = zone_regions(polyhedron, prototype, "hard", mu, grow=False,
                           construction="search zones on faces (§5.3)", margin=margin,
                           result=ThreeHardRegions, resolution=resolution)
    assert isinstance(regions, ThreeHardRegions)
    return regions


#: The faces the search combines (the largest), and the grasps sampled on each triple for its
#: prototype (the table's entry; the hand's ``samples`` are not used).
MAX_FACES, SAMPLES = 12, 500


def three_hard_construction(max_faces: int = MAX_FACES, samples: int = SAMPLES) -> Construction:
    """The table's construction for three hard fingers on faces (§5.3), with the
    ``max_faces`` largest faces combined in triples and ``samples`` grasps sampled on each
    (the table's entry is :data:`THREE_HARD`, with the defaults).

    The faces are combined in triples (two fingers may share a face), screened by
    force-direction closure of their friction cones, and given regions by
    :func:`three_hard_regions`. Nguyen's cost for ``c`` required contacts on ``n`` faces is
    ``O(n^c c 2^c)``; the screening removes most triples first.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import synthesize
    >>> found = synthesize(bundled("cube"), 3, "hard", 0.5, top=2,
    ...                    construction=three_hard_construction(max_faces=6)).found
    >>> all(r.certify().holds for r in found), len(found)
    (True, 2)

    References
    ----------
    V.-D. Nguyen, "Constructing force-closure grasps", IJRR 7(3), 1988, §5.3.
    """
    def sites(polyhedron: Polyhedron, hand: Hand):
        """Step 1: triples of the ``max_faces`` largest faces (two fingers may share one,
        not all three); ties (equal faces of a symmetric object, and faces whose areas
        differ by no more than the rounding of the object's coordinates: the
        hand's ``resolution``, as the search ranks) to the lower index, so that a moved copy
        gives its fingers the same faces in the same order."""
        areas = [(tie_rounded(f.area / polyhedron.size**2), f.index, None)
                 for f in polyhedron.faces]
        order = [f for _, f, _ in ranked(areas, SPACINGS * hand.resolution, areas=True)]
        yield [t for t in itertools.combinations_with_replacement(order[:max_faces], 3)
               if t[0] != t[2]]

    def prune(polyhedron: Polyhedron, sites, hand: Hand) -> list[bool]:
        """Step 2: force-direction closure of the three faces' friction cones."""
        return [force_direction_closure_of_faces([polyhedron.faces[f].normal for f in t],
                                                 hand.mu) for t in sites]

    def build(polyhedron: Polyhedron, triple, hand: Hand) -> ThreeHardRegions | None:
        """Step 4: the best of ``samples`` grasps on the triple by epsilon (each grasp's
        epsilon is its own), and its search zones on the faces."""
        from ...analysis.batch import epsilon_batch

        P, F = prototype_samples(polyhedron, 3, samples, hand.seed, triple)
        normals = np.array([f.normal for f in polyhedron.faces])
        # ranked with the pyramids the search zones are built with (the coordinate axes')
        eps = epsilon_batch(P, normals[F], mu=narrowed(hand.mu, hand.margin), model="hard",
                            orientation="axes")
        best = best_prototypes(P, F, eps, 1)
        return (_around(polyhedron, best[0], hand.mu, hand.margin, hand.resolution) if best
                else None)

    return Construction(
        dim=3, fingers=3, contact="hard", name="maximal", paper="§5.3", method="faces",
        sites=sites, prune=prune, build=build,
        searched=f"every triple of the {max_faces} largest faces whose friction cones have "
                 f"force-direction closure, around the best of {samples} grasps on each")


THREE_HARD = three_hard_construction()
