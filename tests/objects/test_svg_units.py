"""The file's units carried to the output: an SVG says what its coordinates measure.

Ground truth: the physical size a renderer gives the drawing (svgelements, with the
root's width/height applied: CSS px at 96 per inch), and the attributes of files
written by others (matplotlib's own icons: Sodipodi's ``hand.svg``, 128 pt over a
507.946-unit viewBox).
"""

from __future__ import annotations

import io
import json
import xml.etree.ElementTree as ET
from pathlib import Path

import matplotlib
import numpy as np
import pytest
import svgelements as se

matplotlib.use("Agg")

from forceclosure.app.cli import main
from forceclosure.objects.io import load_object, polygon_from_svg
from forceclosure.objects.svg import svg_units

NS = 'xmlns="http://www.w3.org/2000/svg"'
PLATE = "M10 10 H90 V40 H60 V30 H40 V40 H10 Z"  # a U-shaped plate, 80 x 30 user units
ICONS = Path(matplotlib.get_data_path()) / "images"


def _svg(root: str, d: str = PLATE) -> str:
    return f'<svg {NS} {root}><path d="{d}"/></svg>'


@pytest.mark.parametrize("root,units", [
    ('width="100mm" height="50mm" viewBox="0 0 100 50"', "mm"),  # Inkscape's way
    ('width="100mm" viewBox="0 0 200 100"', "0.5 mm"),  # width alone sets the scale
    ('width="4in" height="2in" viewBox="0 0 4 2"', "in"),
    ('width="72pt" height="72pt" viewBox="0 0 72 72"', "pt"),  # matplotlib's way
    ('width="100" height="50" viewBox="0 0 100 50"', "px"),  # a bare number is CSS px
    ('width="100px" height="50px" viewBox="0 0 50 25"', "2 px"),
    ('width="100mm" height="50mm"', "px"),  # no viewBox: user units are CSS px
    ("", "px"),
    ('viewBox="0 0 100 50"', None),  # the viewport is the container's: not stated
    ('width="100%" height="100%" viewBox="0 0 100 50"', None),
    ('width="10em" viewBox="0 0 100 50"', None),
    # x and y stretched differently: no one unit
    ('width="100mm" height="100mm" viewBox="0 0 100 50" preserveAspectRatio="none"', None),
    # the default "meet": the smaller scale, 1 mm a unit (x), fits both
    ('width="100mm" height="100mm" viewBox="0 0 100 50"', "mm"),
])
def test_units_from_the_root(root, units):
    assert svg_units(ET.fromstring(_svg(root))) == units
    assert polygon_from_svg(_svg(root)).units == units


@pytest.mark.parametrize("root", ['width="100mm" height="50mm" viewBox="0 0 100 50"',
                                  'width="50mm" height="25mm" viewBox="0 0 100 50"',
                                  'width="3in" height="1in" viewBox="5 5 30 10"',
                                  'width="250px" height="100px" viewBox="0 0 100 40"'])
def test_a_unit_measures_what_a_renderer_draws(root):
    """The polygon's width times its unit is the shape's width as svgelements renders the
    file at its physical size (px, 96 per inch; its mm are 0.0393701 in, 5e-7 off)."""
    p = polygon_from_svg(_svg(root))
    number, _, unit = p.units.rpartition(" ")
    factor = float(number) if number else 1.0
    per_px = {"mm": 25.4 / 96, "in": 1 / 96, "px": 1.0}[unit]
    drawn = se.SVG.parse(io.StringIO(_svg(root)))
    path = next(e for e in drawn.elements() if isinstance(e, se.Path))
    x0, y0, x1, y1 = path.bbox()
    width, height = np.ptp(p.outer, axis=0) * factor
    assert width == pytest.approx((x1 - x0) * per_px, rel=1e-6)
    assert height == pytest.approx((y1 - y0) * per_px, rel=1e-6)


def test_files_nobody_here_wrote():
    # matplotlib's icons: written by matplotlib (72 pt on 72 units) and by Sodipodi
    assert load_object(ICONS / "back.svg").units == "pt"
    hand = load_object(ICONS / "hand.svg")
    assert hand.units == "0.251995 pt"
    # the hand's outline as svgelements renders the file at its size (px -> pt)
    drawn = se.SVG.parse(str(ICONS / "hand.svg"))
    boxes = [e.bbox() for e in drawn.elements() if isinstance(e, se.Shape) and e.bbox()]
    x0, y0, x1, y1 = max(boxes, key=lambda b: (b[2] - b[0]) * (b[3] - b[1]))
    width, height = np.ptp(hand.outer, axis=0) * 0.251995
    assert width == pytest.approx((x1 - x0) * 72 / 96, rel=1e-5)  # the 6 digits printed
    assert height == pytest.approx((y1 - y0) * 72 / 96, rel=1e-5)


def test_files_without_units_say_nothing(tmp_path, capsys):
    path = tmp_path / "plate.geojson"
    path.write_text(json.dumps({"type": "Polygon", "coordinates": [
        [[0, 0], [4, 0], [4, 1], [0, 1], [0, 0]]]}))
    assert load_object(path).units is None
    assert main(["inspect", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["units"] is None
    assert main(["inspect", str(path)]) == 0
    assert "size 4.12311 (bounding-box diagonal)" in capsys.readouterr().out
    assert main(["synthesize", str(path), "--mu", "0.3", "--top", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["units"] is None
    assert main(["inspect", "cube", "--json"]) == 0  # a polyhedron: the key too
    assert json.loads(capsys.readouterr().out)["units"] is None


def test_units_in_the_outputs(tmp_path, capsys):
    path = tmp_path / "plate.svg"
    path.write_text(_svg('width="100mm" height="50mm" viewBox="0 0 100 50"'))
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert "area 2200 mm², perimeter 240 mm" in out and "size 85.44 mm (" in out
    assert main(["inspect", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["units"] == "mm"
    assert main(["synthesize", str(path), "--mu", "0.3", "--top", "2"]) == 0
    out = capsys.readouterr().out
    assert "coordinates in mm" in out
    # the best pair: the plate's two outer sides, x = 10 and x = 90, 80 mm apart
    assert "shortest segment 23.91 mm (" in out
    assert main(["synthesize", str(path), "--mu", "0.3", "--top", "2", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["units"] == "mm" and record["size"] == pytest.approx(np.hypot(80, 30))
    half = tmp_path / "half.svg"  # one unit is half a millimetre
    half.write_text(_svg('width="50mm" height="25mm" viewBox="0 0 100 50"'))
    assert main(["synthesize", str(half), "--mu", "0.3", "--top", "1"]) == 0
    out = capsys.readouterr().out
    assert "coordinates in units of 0.5 mm" in out and "23.91 (units of 0.5 mm)" in out


def test_units_on_the_pictures_axes():
    from forceclosure.pictures.plot import plot_object, plot_regions
    from forceclosure.synthesis.best import synthesize

    plate = polygon_from_svg(_svg('width="100mm" height="50mm" viewBox="0 0 100 50"'))
    found = synthesize(plate, 2, "hard", 0.3, top=2).found
    ax = plot_regions(found).axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x (mm)", "y (mm)")
    pytest.importorskip("plotly")
    from forceclosure.pictures.view import planar_figure

    layout = planar_figure(found).layout
    assert (layout.xaxis.title.text, layout.yaxis.title.text) == ("x (mm)", "y (mm)")
    bare = polygon_from_svg(_svg('viewBox="0 0 100 50"'))
    assert plot_object(bare).axes[0].get_xlabel() == ""
