"""The grasps' labels in the synthesis picture do not print on top of each other.

Measured on the drawing matplotlib makes (Agg): every label's box on the screen
(``Text.get_window_extent(renderer)``), pairwise disjoint, and each label still beside
a region of its own grasp. The polygons are chosen so that several grasps share edges:
before the labels were placed, the plate's five three-finger grasps had 15 pairs of
overprinted labels, the notch's two-finger grasps and vertex grasps 2.
"""

from __future__ import annotations

import itertools

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
from matplotlib.backends.backend_agg import FigureCanvasAgg

from forceclosure.objects import Polygon, bundled
from forceclosure.pictures.plot import on_vertex, plot_regions
from forceclosure.synthesis.best import synthesize

PLATE = Polygon.from_points([[10, 10], [90, 10], [90, 40], [60, 40], [60, 30], [40, 30],
                             [40, 40], [10, 40]], name="plate")
NOTCH = Polygon.from_points([[0, 0], [4, 0], [4, 1], [2.5, 1], [2.5, 1.0000015], [1.5, 1.5],
                             [0, 1.5]], name="notch")


def _segment_distance(p, a, b) -> float:
    d = b - a
    t = np.clip((p - a) @ d / (d @ d), 0.0, 1.0) if d @ d > 0 else 0.0
    return float(np.linalg.norm(a + t * d - p))


@pytest.mark.parametrize("polygon, fingers, corners", [
    (PLATE, 3, 0), (NOTCH, 2, 3), (NOTCH, 3, 0), (bundled("bracket"), 2, 3),
    (bundled("square"), 3, 0),
])
def test_labels_do_not_overprint(polygon, fingers, corners):
    found = synthesize(polygon, fingers, "hard", 0.3, top=5).found
    extra = synthesize(polygon, 2, "soft", 0.3, top=corners,
                       construction="vertices").found if corners else []
    grasps = [*found, *extra]
    fig = plot_regions(grasps)
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    ax = fig.axes[0]
    texts = ax.texts
    sets = [g for g in grasps if not on_vertex(g)]
    # every finger of every grasp numbered (vertex grasps: v1... at their vertex and other
    # finger), nothing lost
    numbers = sorted(t.get_text() for t in texts if not t.get_text().startswith("v"))
    assert numbers == sorted(str(r + 1) for r, g in enumerate(sets) for _ in g.edges)
    assert len(sets) >= 2 and len(set(k for g in sets for k in g.edges)) < sum(
        len(g.edges) for g in sets)  # some edge is shared: the case that overprinted
    boxes = [t.get_window_extent(renderer) for t in texts]
    for (i, a), (j, b) in itertools.combinations(enumerate(boxes), 2):
        assert not a.overlaps(b), (texts[i].get_text(), texts[j].get_text(), a, b)
    # and each number still beside one of its grasp's segments (within a fifth of the size)
    to_data = ax.transData.inverted()
    for t, box in zip(texts, boxes, strict=True):
        if t.get_text().startswith("v"):
            continue
        centre = to_data.transform([(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2])
        g = sets[int(t.get_text()) - 1]
        near = min(_segment_distance(centre, np.asarray(a), np.asarray(b))
                   for a, b in g.points)
        assert near < 0.2 * polygon.size, (t.get_text(), near)


def test_labels_hold_when_saved(tmp_path):
    """Saved as PNG (another dpi, a tight box), the labels stay apart: their offsets are in
    points from their anchors."""
    fig = plot_regions(synthesize(PLATE, 3, "hard", 0.3, top=5).found, tmp_path / "p.png")
    assert (tmp_path / "p.png").stat().st_size > 0
    fig.set_dpi(130)
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    boxes = [t.get_window_extent(renderer) for t in fig.axes[0].texts]
    assert not any(a.overlaps(b) for a, b in itertools.combinations(boxes, 2))
