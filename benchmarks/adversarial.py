"""Adversarial grasps whose force-closure verdict is known exactly (issue 26).

Each case is one of a few dozen base grasps, built in rational arithmetic so that its true
verdict (Theorem 1, exact circular cones) follows from its construction, then turned, scaled
and moved *exactly*: a signed permutation of the axes (space) or an integer 3-4-5 rotation
(the plane), a scale ``2**k`` with ``k`` in ``-13..10`` (about 1e-4 to 1e3) and, three times in
four, a translation by integers of 1e4 to 9e8 (divided by 10 until every coordinate is exact in
floating point). So the floats every tool receives are exactly the constructed grasp, and
force closure being invariant under similarities, the truth carries over. Normals are integer
vectors of rational length (axes, 3-4-5 directions), not normalised: tools normalise them, as
they must for a mesh's normals.

The families (``BASES``) sit where fast tests fail:

* **on the cone's edge**: a planar or spatial pair whose line makes exactly the angle
  ``atan(mu)`` with a normal (``mu`` = 3/4, the 3-4-5 angle, 1 and 1/2): not closure
  (Corollary 3 asks for the line strictly inside both cones; for antiparallel normals, or in
  the plane, it is an "iff");
* **just inside / just outside**: the same line turned by about ``2**-20`` radians;
* **rank-deficient**: two hard fingers in space (rank 5, whatever the line), three hard
  fingers on one line, frictionless pairs and triples, a planar form-closure grasp lifted into
  space, seven frictionless fingers on a box's four side faces (Theorem 1's first half);
* **outside**: a finger whose normal points at the other (both push the same way), a square
  whose four frictionless fingers all turn it one way, a box with no finger on one face;
* **closure**: well inside the cones, three hard fingers in non-marginal equilibrium with
  friction down to ``2**-20`` (Corollary 4), four frictionless fingers in a pinwheel, seven
  frictionless fingers on a box (its truth computed once exactly and asserted by the tests).

``truth`` is one of ``closure``, ``boundary``, ``rank-deficient``, ``outside``; every
case's truth is checked independently in rationals by ``tests/test_adversarial.py`` (and by
``bench_adversarial.py --check``): closure by an inscribed square pyramid that is closed,
not closure by a circumscribed one that is not, ranks exactly.

    uv run python benchmarks/adversarial.py [--seed 0] [--copies 21]

prints the families and the count of each truth.
"""

from __future__ import annotations

import argparse
from collections import Counter
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

TRUTHS = ("closure", "boundary", "rank-deficient", "outside")

Vector = tuple[Fraction, ...]


@dataclass(frozen=True)
class Case:
    """One grasp: exact points, integer outward normals, one contact model and friction."""

    family: str
    truth: str
    model: str  # "frictionless", "hard" or "soft" (the paper's uncoupled torque)
    mu: Fraction
    points: tuple[Vector, ...]
    normals: tuple[tuple[int, ...], ...]

    @property
    def closure(self) -> bool:
        """Whether the grasp is force-closure (exact circular cones)."""
        return self.truth == "closure"

    @property
    def dim(self) -> int:
        return len(self.points[0])

    def arrays(self) -> tuple[np.ndarray, np.ndarray, float]:
        """Points ``(k, d)``, normals ``(k, d)`` and ``mu`` as floats: exactly the case."""
        return (np.array([[float(x) for x in p] for p in self.points]),
                np.array(self.normals, dtype=float), float(self.mu))


def _v(*xs) -> Vector:
    return tuple(Fraction(x) for x in xs)


def _base(family, truth, model, mu, points, normals) -> Case:
    return Case(family, truth, model, Fraction(mu), tuple(_v(*p) for p in points),
                tuple(tuple(int(x) for x in n) for n in normals))


def _planar_pair(family, truth, mu, u, n_q=(0, 1)) -> Case:
    """``p`` at the origin pushed up (outward normal down), ``q = u``."""
    return _base(family, truth, "hard", mu, [(0, 0), u], [(0, -1), n_q])


def _spatial_pair(family, truth, model, mu, u, n_q=(0, 0, 1)) -> Case:
    return _base(family, truth, model, mu, [(0, 0, 0), u], [(0, 0, -1), n_q])


BIG = 2**20  # lines turned by about 2**-20 radians from the cone's edge
SMALL = Fraction(1, 2**12)


def _pinwheel(family, truth, a, b, c, d, lift=False) -> Case:
    """Four frictionless fingers on the square [-1, 1]^2: left at height ``a``, right at
    ``b``, bottom at abscissa ``c``, top at ``d``. Their wrenches (1, 0, -a), (-1, 0, b),
    (0, 1, c), (0, -1, -d) are closed iff (b - a)(c - d) < 0; one of the factors zero is the
    boundary, both zero rank 2, the same sign outside."""
    pts = [(-1, a), (1, b), (c, -1), (d, 1)]
    nrm = [(-1, 0), (1, 0), (0, -1), (0, 1)]
    if lift:  # the same fingers in space, at z = 0 with normals in the plane: rank 3
        pts, nrm = [(*p, 0) for p in pts], [(*n, 0) for n in nrm]
    return _base(family, truth, "frictionless", 0, pts, nrm)


#: Seven frictionless fingers on the box [-1, 1]^3 that are form-closed (checked exactly).
BOX7 = ([(-1, Fraction(-3, 4), Fraction(-1, 4)), (1, Fraction(-3, 4), Fraction(1, 2)),
         (Fraction(1, 4), -1, Fraction(-3, 4)), (Fraction(-1, 4), 1, Fraction(1, 2)),
         (0, Fraction(-3, 4), -1), (Fraction(1, 4), Fraction(1, 2), 1),
         (Fraction(1, 2), 1, 0)],
        [(-1, 0, 0), (1, 0, 0), (0, -1, 0), (0, 1, 0), (0, 0, -1), (0, 0, 1), (0, 1, 0)])

#: Three fingers on the circle of radius 5 (3-4-5 points), normals radial: their inward
#: normals balance with weights 6/5, 1, 1, strictly inside any cone (Corollary 4).
CIRCLE3 = ([(-5, 0, 0), (3, 4, 0), (3, -4, 0)], [(-1, 0, 0), (3, 4, 0), (3, -4, 0)])

BASES: tuple[Case, ...] = (
    # planar pairs (Corollary 3, exact in the plane)
    _planar_pair("planar pair, line on the cone's edge", "boundary", Fraction(3, 4), (3, 4)),
    _planar_pair("planar pair, just inside", "closure", Fraction(3, 4), (3 * BIG - 1, 4 * BIG)),
    _planar_pair("planar pair, just outside", "outside", Fraction(3, 4), (3 * BIG + 1, 4 * BIG)),
    _planar_pair("planar pair, well inside", "closure", Fraction(3, 4), (1, 4)),
    _planar_pair("planar pair, well outside", "outside", Fraction(3, 4), (4, 1)),
    _planar_pair("planar pair, one line on the edge, one along the normal", "boundary",
                 Fraction(3, 4), (3, 4), n_q=(3, 4)),
    _planar_pair("planar pair, line on the cone's edge", "boundary", 1, (1, 1)),
    _planar_pair("planar pair, just inside", "closure", 1, (BIG - 1, BIG)),
    _planar_pair("planar pair, just outside", "outside", 1, (BIG + 1, BIG)),
    _planar_pair("planar pair, line on the cone's edge", "boundary", Fraction(1, 2), (1, 2)),
    _planar_pair("planar pair, frictionless, antipodal", "rank-deficient", 0, (0, 4)),
    _planar_pair("planar pair, both push the same way", "outside", Fraction(3, 4), (0, 4),
                 n_q=(0, -1)),
    # planar, three and four frictionless fingers
    _base("planar, three frictionless fingers", "outside", "frictionless", 0,
          [(-1, Fraction(1, 2)), (1, Fraction(-1, 2)), (0, -1)], [(-1, 0), (1, 0), (0, -1)]),
    _pinwheel("planar pinwheel, four frictionless", "closure",
              Fraction(1, 2), Fraction(-1, 2), Fraction(1, 2), Fraction(-1, 2)),
    _pinwheel("planar pinwheel, four frictionless, barely turned", "closure",
              SMALL, -SMALL, Fraction(1, 2), Fraction(-1, 2)),
    _pinwheel("planar four frictionless, one pair aligned", "boundary",
              Fraction(1, 2), Fraction(1, 2), Fraction(1, 2), Fraction(-1, 2)),
    _pinwheel("planar four frictionless, both pairs aligned", "rank-deficient",
              Fraction(1, 2), Fraction(1, 2), Fraction(1, 2), Fraction(1, 2)),
    _pinwheel("planar four frictionless, all turn one way", "outside",
              Fraction(-1, 2), Fraction(1, 2), Fraction(1, 2), Fraction(-1, 2)),
    _pinwheel("planar four frictionless, all turn one way, barely", "outside",
              -SMALL, SMALL, Fraction(1, 2), Fraction(-1, 2)),
    # spatial pairs: soft fingers with antiparallel normals (Corollary 3 is an "iff"), and
    # hard fingers, never closed (rank 5: the rotation about the line through them)
    _spatial_pair("soft pair, line on the cone's edge", "boundary", "soft", Fraction(3, 4),
                  (3, 0, 4)),
    _spatial_pair("soft pair, just inside", "closure", "soft", Fraction(3, 4),
                  (3 * BIG - 1, 0, 4 * BIG)),
    _spatial_pair("soft pair, just outside", "outside", "soft", Fraction(3, 4),
                  (3 * BIG + 1, 0, 4 * BIG)),
    _spatial_pair("soft pair, well inside", "closure", "soft", Fraction(3, 4), (1, 0, 4)),
    _spatial_pair("soft pair, both push the same way", "outside", "soft", Fraction(3, 4),
                  (0, 0, 4), n_q=(0, 0, -1)),
    _spatial_pair("soft pair, line on the cone's edge", "boundary", "soft", 1, (1, 0, 1)),
    _spatial_pair("soft pair, just inside", "closure", "soft", 1, (BIG - 1, 0, BIG)),
    _spatial_pair("hard pair, line well inside (rank 5)", "rank-deficient", "hard",
                  Fraction(3, 4), (1, 0, 4)),
    _spatial_pair("hard pair, line on the cone's edge (rank 5)", "rank-deficient", "hard",
                  Fraction(3, 4), (3, 0, 4)),
    _spatial_pair("hard pair, antipodal (rank 5)", "rank-deficient", "hard", 1, (0, 0, 4)),
    # spatial, three and more fingers
    _base("three hard fingers on a circle", "closure", "hard", 1, *CIRCLE3),
    _base("three hard fingers on a circle, friction 2^-10", "closure", "hard",
          Fraction(1, 2**10), *CIRCLE3),
    _base("three frictionless fingers on a circle", "rank-deficient", "frictionless", 0,
          *CIRCLE3),
    _base("three hard fingers on a box's sides, friction 2^-20", "closure", "hard",
          Fraction(1, 2**20), [(-1, 0, 0), (1, Fraction(1, 2), 0), (1, Fraction(-1, 2), 0)],
          [(-1, 0, 0), (1, 0, 0), (1, 0, 0)]),
    _base("three hard fingers on one line", "rank-deficient", "hard", 1,
          [(-1, 0, 0), (1, 0, 0), (3, 0, 0)], [(-1, 0, 0), (1, 0, 0), (1, 0, 0)]),
    _pinwheel("planar pinwheel lifted into space", "rank-deficient",
              Fraction(1, 2), Fraction(-1, 2), Fraction(1, 2), Fraction(-1, 2), lift=True),
    _base("seven frictionless fingers on a box", "closure", "frictionless", 0, *BOX7),
    _base("seven frictionless fingers on a box's four sides", "rank-deficient",
          "frictionless", 0,
          [(-1, Fraction(-3, 4), Fraction(-1, 4)), (1, Fraction(-3, 4), Fraction(1, 2)),
           (Fraction(1, 4), -1, Fraction(-3, 4)), (Fraction(-1, 4), 1, Fraction(1, 2)),
           (-1, Fraction(1, 2), Fraction(1, 2)), (1, Fraction(1, 2), Fraction(-1, 2)),
           (Fraction(1, 2), 1, 0)],
          [(-1, 0, 0), (1, 0, 0), (0, -1, 0), (0, 1, 0), (-1, 0, 0), (1, 0, 0), (0, 1, 0)]),
    _base("seven frictionless fingers on a box, none on one face", "outside",
          "frictionless", 0, [BOX7[0][0], (-1, Fraction(1, 2), Fraction(1, 2)), *BOX7[0][2:]],
          [BOX7[1][0], (-1, 0, 0), *BOX7[1][2:]]),
)

#: Integer rotations of the plane (3-4-5 angles, times 5) and a quarter turn.
PLANAR_TURNS = (((1, 0), (0, 1)), ((3, -4), (4, 3)), ((4, -3), (3, 4)), ((0, -1), (1, 0)))


def _exact(x: Fraction) -> bool:
    return Fraction(float(x)) == x


def _place(case: Case, rng: np.random.Generator) -> Case:
    """The case turned, scaled by ``2**k`` and moved by integers, all exactly."""
    d = case.dim
    if d == 2:
        turn = np.array(PLANAR_TURNS[rng.integers(len(PLANAR_TURNS))], dtype=object)
    else:
        turn = np.zeros((3, 3), dtype=object)
        turn[np.arange(3), rng.permutation(3)] = rng.choice([-1, 1], 3)
    scale = Fraction(2) ** int(rng.integers(-13, 11))
    points = [tuple(sum((turn[i, j] * p[j] for j in range(d)), Fraction(0)) * scale
                    for i in range(d)) for p in case.points]
    normals = tuple(tuple(int(sum(turn[i, j] * n[j] for j in range(d))) for i in range(d))
                    for n in case.normals)
    offset = [int(rng.choice([-1, 1]) * rng.integers(1, 10)) * 10 ** int(rng.integers(4, 9))
              for _ in range(d)]
    if rng.random() < 0.25:
        offset = [0] * d
    while True:  # the largest translation that keeps every coordinate exact
        moved = tuple(tuple(x + o for x, o in zip(p, offset, strict=True)) for p in points)
        if all(_exact(x) for p in moved for x in p):
            break
        offset = [int(o / 10) for o in offset]
    return Case(case.family, case.truth, case.model, case.mu, moved, normals)


def adversarial_set(seed: int = 0, copies: int = 21) -> list[Case]:
    """``copies`` placements of every base case (the first as built), in a seeded order.

    Examples
    --------
    >>> cases = adversarial_set(seed=0, copies=2)
    >>> len(cases) == 2 * len(BASES), {c.truth for c in cases} == set(TRUTHS)
    (True, True)
    """
    rng = np.random.default_rng(seed)
    return list(BASES) + [_place(base, rng) for _ in range(copies - 1) for base in BASES]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--copies", type=int, default=21)
    args = parser.parse_args()
    cases = adversarial_set(args.seed, args.copies)
    print(f"{len(cases)} cases (seed {args.seed}): "
          + ", ".join(f"{n} {t}" for t, n in sorted(Counter(c.truth for c in cases).items())))
    for base in BASES:
        print(f"  {base.truth:>14}  {base.model:>12}  mu {base.mu!s:>9}  {base.family}")


if __name__ == "__main__":
    main()
