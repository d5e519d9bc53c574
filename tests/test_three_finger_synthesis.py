"""Three fingers with friction (Corollary 4 with a common centre), checked by Theorem 1."""

import itertools
import math

import numpy as np
import pytest

from forceclosure import InputError, Verdict, analyze, point_contact
from forceclosure.cli import main
from forceclosure.objects import Polygon, bundled, glyph
from forceclosure.synthesis import best_three_finger_regions, three_finger_regions


@pytest.mark.parametrize("polygon", [bundled(n) for n in ("triangle", "hexagon", "star",
                                                          "wrench-head", "bracket")]
                         + [glyph("A")], ids=lambda p: p.name)
def test_every_triple_in_every_region_is_force_closure(polygon):
    rng = np.random.default_rng(4)
    mu = 0.3
    found = best_three_finger_regions(polygon, mu, top=3)
    for r in found:
        assert r.certify().holds
        es = [polygon.edges[k] for k in r.edges]
        samples = list(itertools.product(*r.segments)) + [
            tuple(rng.uniform(u, v) for u, v in r.segments) for _ in range(80)]
        for ts in samples:
            grasp = [point_contact(e.point(t), e.normal, "hard", mu)
                     for e, t in zip(es, ts, strict=True)]
            assert analyze(grasp).verdict is Verdict.CLOSURE, (polygon.name, r.edges, ts)
    if polygon.name in ("triangle", "hexagon", "wrench-head"):
        assert found


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.5])
def test_regular_polygons_closed_form(mu):
    """Around a regular n-gon with inradius r, lines meeting at the centre allow each
    finger 2 r tan(atan(mu) - margin), up to the side's length."""
    for n, edges in ((3, (0, 1, 2)), (6, (0, 2, 4))):
        polygon = Polygon.regular(n)
        r = three_finger_regions(polygon, edges, mu)
        inradius = math.cos(math.pi / n)
        want = min(2 * inradius * math.tan(math.atan(mu) - 1e-3), polygon.edges[0].length)
        if mu >= math.tan(math.pi / 6):  # (b) fails: a choice of directions fits a half-plane
            assert r is None
        else:
            assert r.min_length == pytest.approx(want, rel=1e-3)
            np.testing.assert_allclose(r.centre, [0, 0], atol=1e-6)


def test_refusals_and_command(capsys, tmp_path):
    with pytest.raises(InputError, match="three different edges"):
        three_finger_regions(bundled("triangle"), (0, 0, 1), 0.3)
    picture = tmp_path / "three.png"
    assert main(["synthesize", "triangle", "--fingers", "3", "--mu", "0.3",
                 "--plot", str(picture)]) == 0
    assert "1. edge 0" in capsys.readouterr().out
    assert picture.read_bytes()[:4] == b"\x89PNG"
