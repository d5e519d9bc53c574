"""SVG files read as a browser draws them: checked against closed forms and third-party files."""

import io
import subprocess
import sys

import matplotlib
import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.font_manager import FontProperties
from matplotlib.patches import PathPatch
from matplotlib.textpath import TextPath

from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.objects.io import load_object, polygon_from_svg
from forceclosure.objects.svg import SVG_TOLERANCE

SVG_NS = 'xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"'


def inkscape(body: str, width="210mm", height="297mm", viewbox="0 0 210 297") -> str:
    """A document the way Inkscape writes one: namespaces, a layer group, styles."""
    return f"""<?xml version="1.0" encoding="UTF-8" standalone="no"?>
<svg width="{width}" height="{height}" viewBox="{viewbox}" version="1.1" id="svg1"
   xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
   xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd"
   {SVG_NS}>
  <sodipodi:namedview id="namedview1" pagecolor="#ffffff" inkscape:document-units="mm"/>
  <defs id="defs1"/>
  <g inkscape:label="Layer 1" inkscape:groupmode="layer" id="layer1">
    {body}
  </g>
</svg>"""


def tolerance(p) -> float:
    """The stated tolerance: SVG_TOLERANCE of the shape's bounding-box diagonal (an upper
    bound: the polygon's box lies inside the curve's)."""
    return SVG_TOLERANCE * p.size * (1 + 1e-9)


def edge_midpoints(ring):
    return (ring + np.roll(ring, -1, axis=0)) / 2


def test_nested_group_transforms_are_applied():
    body = ('<g transform="translate(50,0)"><g transform="scale(2)">'
            '<path style="fill:#000000;stroke:none" d="M 0,0 H 4 V 3 H 0 Z" id="path1"/>'
            '</g></g>')
    p = polygon_from_svg(inkscape(body, width="100mm", height="100mm",
                                  viewbox="0 0 100 100"))
    # drawn at x 50..58, y 0..6 (y down); read y up: y' = 100 - y
    assert p.bounds.tolist() == [[50.0, 94.0], [58.0, 100.0]]
    assert p.area == 48.0 and p.warnings == ()


def test_one_transform_list_as_written():
    p = polygon_from_svg(f'<svg {SVG_NS}><g transform="translate(50,0) scale(2)">'
                         '<path d="M0 0 H4 V4 H0 Z"/></g></svg>')
    assert p.bounds.tolist() == [[50.0, -8.0], [58.0, 0.0]] and p.area == 64.0


def test_element_transform_rotation_and_skew():
    # a 4 x 2 rectangle rotated by 90 degrees about (0, 0): drawn at x -2..0, y 0..4
    p = polygon_from_svg(f'<svg {SVG_NS}><rect width="4" height="2" '
                         'transform="rotate(90)"/></svg>')
    assert np.allclose(p.bounds, [[-2, -4], [0, 0]], atol=1e-12)
    assert p.area == pytest.approx(8.0, rel=1e-12)
    # skewX(45) maps the unit square to a parallelogram of area 1, x' = x + y
    q = polygon_from_svg(f'<svg {SVG_NS}><rect width="1" height="1" '
                         'transform="skewX(45)"/></svg>')
    assert q.area == pytest.approx(1.0, rel=1e-12)
    assert np.allclose(q.bounds, [[0, -1], [2, 0]], atol=1e-12)


def test_viewbox_with_units_reads_user_units():
    body = '<rect x="10" y="20" width="30" height="40" style="fill:#ff0000"/>'
    p = polygon_from_svg(inkscape(body))
    # millimetres of the viewBox, y up from the page's bottom edge (297 mm)
    assert p.bounds.tolist() == [[10.0, 237.0], [40.0, 277.0]] and p.area == 1200.0
    # a viewBox not at the origin: its bottom-left corner becomes (0, 0)
    q = polygon_from_svg(f'<svg {SVG_NS} width="10cm" height="5cm" viewBox="10 20 100 50">'
                         '<rect x="10" y="20" width="5" height="5"/></svg>')
    assert q.bounds.tolist() == [[0.0, 45.0], [5.0, 50.0]]


@pytest.mark.parametrize("inner,bounds", [
    # a viewport at (10, 10), 20 wide, showing viewBox 0 0 10 10: scale 2
    ('<svg x="10" y="10" width="20" height="20" viewBox="0 0 10 10">'
     '<rect width="10" height="10"/></svg>', [[10, 70], [30, 90]]),
    # without a viewBox a nested <svg> only moves its content to x, y
    ('<svg x="10" y="10"><svg x="1" y="2"><rect width="10" height="10"/></svg></svg>',
     [[11, 78], [21, 88]]),
    # attributes that mean nothing on a group are not inherited by the rect
    ('<g x="7" y="7" width="50"><rect width="10" height="10"/></g>', [[0, 90], [10, 100]]),
])
def test_nested_viewports(inner, bounds):
    p = polygon_from_svg(f'<svg {SVG_NS} viewBox="0 0 100 100">{inner}</svg>')
    assert p.bounds.tolist() == bounds


def test_lengths_with_units_as_a_browser_reads_them():
    # 1in = 96 user units (CSS px) and 1 mm = 96 / 25.4
    p = polygon_from_svg(f'<svg {SVG_NS}><rect width="1in" height="25.4mm"/></svg>')
    assert p.area == pytest.approx(96.0 * 96.0, rel=1e-12)


def test_defs_are_not_drawn_but_use_is():
    small = '<rect id="small" width="1" height="1"/>'
    defs = ('<defs><path id="big" d="M0 0 H10 V10 H0 Z"/></defs>'
            '<symbol id="sym"><rect width="50" height="50"/></symbol>'
            '<mask id="m"><rect width="60" height="60" fill="white"/></mask>'
            '<clipPath id="c"><rect width="70" height="70"/></clipPath>')
    p = polygon_from_svg(f'<svg {SVG_NS}>{defs}{small}</svg>')
    assert p.area == 1.0 and p.warnings == ()  # nothing else is drawn
    with pytest.raises(InputError, match="'big' is not drawn"):
        polygon_from_svg(f'<svg {SVG_NS}>{defs}{small}</svg>', part="big")
    for href in ('href="#big"', 'xlink:href="#big"'):
        q = polygon_from_svg(f'<svg {SVG_NS}>{defs}<use id="u" {href} x="5" y="-20"/>{small}'
                             '</svg>')
        assert q.area == 100.0 and q.bounds.tolist() == [[5.0, 10.0], [15.0, 20.0]]
        assert '<path id="big"> in <use id="u">' in q.warnings[0]
    # a symbol (without its own viewBox) drawn by a <use>
    s = polygon_from_svg(f'<svg {SVG_NS}>{defs}<use href="#sym" x="1"/></svg>')
    assert s.area == 2500.0 and s.bounds.tolist() == [[1.0, -50.0], [51.0, 0.0]]


def test_hidden_elements_are_not_drawn():
    p = polygon_from_svg(f'<svg {SVG_NS}><rect width="9" height="9" style="display:none"/>'
                         '<g visibility="hidden"><rect width="8" height="8"/></g>'
                         '<rect width="2" height="3"/></svg>')
    assert p.area == 6.0 and p.warnings == ()


def test_rect_area_is_exact_and_straight_edges_add_no_vertices():
    p = polygon_from_svg(f'<svg {SVG_NS}><rect x="0.5" y="1.25" width="3.75" height="2.5"/>'
                         '</svg>')
    assert p.area == 3.75 * 2.5 and len(p.outer) == 4 and p.warnings == ()


def test_rounded_rect_within_the_stated_tolerance():
    w, h, r = 10.0, 6.0, 2.0
    p = polygon_from_svg(f'<svg {SVG_NS}><rect width="{w}" height="{h}" rx="{r}"/></svg>')
    exact = w * h - (4 - np.pi) * r * r
    tol = tolerance(p)
    perimeter = 2 * (w + h) - 8 * r + 2 * np.pi * r
    assert exact - perimeter * tol <= p.area <= exact
    assert p.bounds.tolist() == [[0.0, -h], [w, 0.0]]  # the straight sides are exact
    # every vertex on the boundary: on a straight side, or at distance r from a corner centre
    for x, y in p.outer:
        y = -y  # back to the drawing's y down
        cx, cy = min(max(x, r), w - r), min(max(y, r), h - r)
        on_side = (cx, cy) != (x, y) and (np.isclose(x, 0) or np.isclose(x, w)
                                           or np.isclose(y, 0) or np.isclose(y, h))
        assert on_side or np.hypot(x - cx, y - cy) == pytest.approx(r, rel=1e-12)
    assert any("tessellated" in w for w in p.warnings)


@pytest.mark.parametrize("transform", ["", "translate(3, 4)", "rotate(33) scale(-1, 1)"])
def test_circle_chords_within_the_stated_tolerance(transform):
    r = 5.0
    p = polygon_from_svg(f'<svg {SVG_NS}><circle cx="7" cy="2" r="{r}" '
                         f'transform="{transform}"/></svg>')
    centre = p.outer.mean(axis=0)  # the regular polygon's centre is the circle's
    tol = tolerance(p)
    assert np.allclose(np.linalg.norm(p.outer - centre, axis=1), r, rtol=1e-12)
    sag = r - np.linalg.norm(edge_midpoints(p.outer) - centre, axis=1)
    assert np.all(sag >= 0) and sag.max() <= tol
    assert sag.max() > tol / 4  # not needlessly fine
    assert np.pi * r * r - 2 * np.pi * r * tol <= p.area <= np.pi * r * r
    assert f"({SVG_TOLERANCE:g} of the shape's size)" in p.warnings[0]


def test_ellipse_and_skewed_circle_within_the_stated_tolerance():
    a, b = 6.0, 2.0
    p = polygon_from_svg(f'<svg {SVG_NS}><ellipse rx="{a}" ry="{b}"/></svg>')
    tol = tolerance(p)
    x, y = p.outer.T
    assert np.allclose((x / a) ** 2 + (y / b) ** 2, 1, rtol=1e-12)
    t = np.linspace(0, 2 * np.pi, 200_001)
    dense = np.column_stack([a * np.cos(t), b * np.sin(t)])  # spacing 1.2e-4 << tol
    for m in edge_midpoints(p.outer):
        assert np.min(np.linalg.norm(dense - m, axis=1)) <= tol
    perimeter = 2 * np.pi * a
    assert np.pi * a * b - perimeter * tol <= p.area <= np.pi * a * b
    # skewX(30) keeps area: x' = x + tan(30) y; undoing it puts vertices back on the circle
    q = polygon_from_svg(f'<svg {SVG_NS}><circle r="3" transform="skewX(30)"/></svg>')
    qx, qy = q.outer.T
    back = np.column_stack([qx - np.tan(np.pi / 6) * (-qy), -qy])
    assert np.allclose(np.linalg.norm(back, axis=1), 3, rtol=1e-12)
    assert np.pi * 9 - 4 * np.pi * 3 * tolerance(q) <= q.area <= np.pi * 9


@pytest.mark.parametrize("flags,up", [("0 1", True), ("0 0", False)])
def test_arc_half_disk(flags, up):
    p = polygon_from_svg(f'<svg {SVG_NS}><path d="M0 0 A 5 5 0 {flags} 10 0 Z"/></svg>')
    # sweep-flag 1 turns clockwise on screen (y down): over the top, so y up after reading
    assert np.allclose(p.bounds, [[0, 0], [10, 5]] if up else [[0, -5], [10, 0]], atol=1e-12)
    on_arc = np.abs(np.linalg.norm(p.outer - [5, 0], axis=1) - 5) <= 1e-12
    assert on_arc.all()  # the two ends of the diameter are on the circle too
    half = np.pi * 25 / 2
    assert half - np.pi * 5 * tolerance(p) <= p.area <= half


def test_quadratic_bezier_area_closed_form():
    # the parabola through (0, 0), (5, 5), (10, 0): area 2/3 * base * height
    p = polygon_from_svg(f'<svg {SVG_NS}><path d="M0 0 Q 5 10 10 0 Z"/></svg>')
    exact = 2 / 3 * 10 * 5
    assert exact - 12 * tolerance(p) <= p.area <= exact


def test_cubic_bezier_against_dense_samples():
    ctrl = np.array([[0, 0], [0, 10], [10, 10], [10, 0]], dtype=float)
    p = polygon_from_svg(f'<svg {SVG_NS}><path d="M0 0 C 0 10 10 10 10 0 Z"/></svg>')

    def bezier(s):
        s = s[:, None]
        xy = ((1 - s) ** 3 * ctrl[0] + 3 * (1 - s) ** 2 * s * ctrl[1]
              + 3 * (1 - s) * s ** 2 * ctrl[2] + s ** 3 * ctrl[3])
        return xy * [1, -1]  # read y up

    s = np.linspace(0, 1, 100_001)
    dense = bezier(s)
    tol = tolerance(p)
    boundary = p.to_shapely().exterior
    assert max(boundary.distance(shapely.Point(q)) for q in dense[::50]) <= tol
    for v in p.outer:  # every vertex on the curve: refine around the nearest sample
        i = int(np.argmin(np.linalg.norm(dense - v, axis=1)))
        fine = bezier(np.linspace(s[max(i - 1, 0)], s[min(i + 1, len(s) - 1)], 10_001))
        assert np.min(np.linalg.norm(fine - v, axis=1)) <= 1e-5 * tol
    exact = float(np.sum((dense[1:, 0] - dense[:-1, 0]) * -(dense[1:, 1] + dense[:-1, 1])) / 2)
    assert exact - 30 * tol <= p.area <= exact + 1e-6


def _matplotlib_svg(text: str) -> tuple[str, TextPath]:
    """A glyph drawn by matplotlib and saved as SVG: a file nobody here wrote."""
    glyph = TextPath((0, 0), text, size=10, prop=FontProperties(family="DejaVu Sans"))
    fig = plt.figure(figsize=(2, 2))
    fig.patch.set_visible(False)  # no page background rectangle
    ax = fig.add_axes((0, 0, 1, 1))  # square axes on a square figure: equal scales
    ax.add_patch(PathPatch(glyph, facecolor="black", edgecolor="none"))
    ax.set_xlim(-1, 11)
    ax.set_ylim(-1, 11)
    ax.set_axis_off()
    out = io.StringIO()
    fig.savefig(out, format="svg")
    plt.close(fig)
    return out.getvalue(), glyph


def _normalised(points):
    points = np.asarray(points, dtype=float)
    lo = points.min(axis=0)
    return (points - lo) / np.ptp(points[:, 0])


def test_letter_l_stays_an_l():
    svg, glyph = _matplotlib_svg("L")
    assert "clip-path" in svg  # matplotlib clips patches to the axes; it cuts nothing here
    p = polygon_from_svg(svg, "L")
    lo, hi = p.bounds
    height = hi[1] - lo[1]
    box = shapely.box
    foot = p.to_shapely().intersection(box(lo[0], lo[1], hi[0], lo[1] + 0.1 * height)).area
    top = p.to_shapely().intersection(box(lo[0], hi[1] - 0.1 * height, hi[0], hi[1])).area
    assert foot > 3 * top  # the wide foot is at the bottom: lowest y
    # the same outline as the font's, up to a translation and scale (no mirror)
    want = _normalised(glyph.vertices[:-1])
    got = _normalised(p.outer)
    assert len(got) == 6
    for v in want:
        assert np.min(np.linalg.norm(got - v, axis=1)) < 1e-5


def test_glyph_with_curves_and_a_hole():
    svg, glyph = _matplotlib_svg("O")
    p = polygon_from_svg(svg, "O")
    assert len(p.holes) == 1 and any("tessellated" in w for w in p.warnings)
    rings = [shapely.Polygon(r) for r in glyph.to_polygons() if len(r) >= 4]
    font = rings[0].symmetric_difference(rings[1])
    scale = np.ptp(p.outer[:, 0]) / np.ptp(np.asarray(font.exterior.coords)[:, 0])
    assert p.area == pytest.approx(font.area * scale ** 2, rel=1e-2)


SEVERAL = (f'<svg {SVG_NS}><rect id="small" width="1" height="1"/>'
           '<g id="grp"><circle id="disk" cx="10" r="3"/></g>'
           '<rect width="2" height="2"/><line x2="9" y2="9" stroke="black"/></svg>')


def test_several_shapes_largest_with_a_warning():
    p = polygon_from_svg(SEVERAL, "several")
    assert p.area == pytest.approx(np.pi * 9, rel=1e-2) and len(p.outer) > 8
    note = next(w for w in p.warnings if "drawn shapes" in w)
    assert '<circle id="disk">' in note and '<rect id="small">' in note and "<rect> #2" in note
    assert any("1 <line>" in w for w in p.warnings)


@pytest.mark.parametrize("part,area", [("small", 1.0), ("disk", None), ("grp", None)])
def test_part_picks_by_id(part, area):
    p = polygon_from_svg(SEVERAL, "several", part=part)
    assert p.area == (area if area else pytest.approx(np.pi * 9, rel=1e-2))
    assert not any("drawn shapes" in w for w in p.warnings)


def test_unknown_part_lists_the_ids():
    with pytest.raises(InputError, match=r"no element with id 'nope'; the ids there are: "
                                         r"small, grp, disk$"):
        polygon_from_svg(SEVERAL, "several", part="nope")


def test_subpaths_holes_islands_and_fill_rule():
    square = "M0 0 H10 V10 H0 Z"
    hole_reversed = "M2 2 V8 H8 V2 Z"  # winds against the outer boundary
    hole_same = "M2 2 H8 V8 H2 Z"  # winds with it
    p = polygon_from_svg(f'<svg {SVG_NS}><path d="{square} {hole_reversed}"/></svg>')
    assert p.area == 64.0 and len(p.holes) == 1
    q = polygon_from_svg(f'<svg {SVG_NS}><path d="{square} {hole_same}"/></svg>')
    assert q.area == 100.0 and not q.holes and "fill-rule nonzero fills it" in q.warnings[0]
    e = polygon_from_svg(f'<svg {SVG_NS}><path fill-rule="evenodd" d="{square} {hole_same}"/>'
                         '</svg>')
    assert e.area == 64.0 and len(e.holes) == 1
    with pytest.raises(InputError, match=r'^isl: <path id="two">: subpath 2 lies outside the '
                                         r"outer boundary \(subpath 1\): a second island"):
        polygon_from_svg(f'<svg {SVG_NS}><path id="two" d="{square} M20 0 H25 V5 Z"/></svg>',
                         "isl")
    # the same island as its own shape is fine: the largest shape is read
    two = polygon_from_svg(f'<svg {SVG_NS}><path d="{square}"/><path d="M20 0 H25 V5 Z"/>'
                           '</svg>')
    assert two.area == 100.0


def test_open_shapes():
    filled = polygon_from_svg(f'<svg {SVG_NS}><polyline points="0,0 4,0 4,3"/></svg>')
    assert filled.area == 6.0  # a fill closes an open outline, as a browser fills it
    with pytest.raises(InputError, match=r'^s: <polyline id="p"> encloses no region: it is an '
                                         "open stroke with no fill$"):
        polygon_from_svg(f'<svg {SVG_NS}><polyline id="p" points="0,0 4,0 4,3" fill="none" '
                         'stroke="black"/></svg>', "s")
    outline = polygon_from_svg(f'<svg {SVG_NS}><polygon points="0,0 4,0 4,3" fill="none" '
                               'stroke="black"/></svg>')
    assert outline.area == 6.0 and "no fill, only a stroke" in outline.warnings[0]


def test_clip_paths():
    clip = '<defs><clipPath id="c"><rect width="5" height="5"/></clipPath></defs>'
    with pytest.raises(InputError, match=r'<rect id="r">: it is cut by its clip-path url\(#c\)'):
        polygon_from_svg(f'<svg {SVG_NS}>{clip}<rect id="r" width="9" height="9" '
                         'clip-path="url(#c)"/></svg>')
    # the clip is in the clipped element's user space: scale(2) makes it 10 x 10
    p = polygon_from_svg(f'<svg {SVG_NS}>{clip}<rect width="4" height="4" '
                         'transform="scale(2)" clip-path="url(#c)"/></svg>')
    assert p.area == 64.0


@pytest.mark.parametrize("body,message", [
    ("<text>L</text>", "no drawn shape (path, polygon, polyline, rect, circle, ellipse) in the "
                       "SVG (1 <text> not read)"),
    ('<path id="x" d="M0 0 L1 0 L1 1 Z 5"/>', "<path id=\"x\">: path command 'Z' takes no "
                                             "numbers"),
    ('<path d="M0 0 L3 0 X 1"/>', "<path>: unknown path command 'X' (at character 11)"),
    ('<path d="M0 0 L3 0 L 1"/>', "path command 'L' has missing or bad numbers"),
    ('<path d="M0 0 L2 2 L2 0 L0 2 Z"/>', "invalid polygon: self-intersection at (1, -1)"),
    ('<polygon points="0 0 1 0 1"/>', "odd number of coordinates"),
    ('<rect width="4" height="4" mask="url(#m)"/>', "it is masked"),
    ('<path d="M0 0 H1e400 V1 Z"/>', "not finite"),
])
def test_bad_svg_one_line(body, message):
    with pytest.raises(InputError) as caught:
        polygon_from_svg(f'<svg {SVG_NS}>{body}</svg>', "bad")
    text = str(caught.value)
    assert "\n" not in text and text.startswith("bad: ") and message in text, text


def test_not_svg():
    with pytest.raises(InputError, match="not valid SVG/XML"):
        polygon_from_svg("<svg><path", "x")
    with pytest.raises(InputError, match="the root element is <html>"):
        polygon_from_svg("<html/>", "x")


def test_cli_part_and_warnings(tmp_path, capsys):
    path = tmp_path / "shape.svg"
    path.write_text(SEVERAL)
    assert main(["inspect", str(path), "--part", "small"]) == 0
    captured = capsys.readouterr()
    assert "area 1 px²," in captured.out and "warning" not in captured.err  # CSS px
    assert main(["inspect", str(path)]) == 0
    assert "warning: shape: 3 drawn shapes" in capsys.readouterr().err
    assert load_object(path, part="disk").area == pytest.approx(np.pi * 9, rel=1e-2)
    other = tmp_path / "t.json"
    other.write_text('{"outer": [[0, 0], [1, 0], [0, 1]]}')
    with pytest.raises(InputError, match="only SVG files"):
        load_object(other, part="x")


def test_cli_bad_svg_exit_2(tmp_path):
    path = tmp_path / "shape.svg"
    path.write_text(SEVERAL)
    proc = subprocess.run([sys.executable, "-m", "forceclosure.app.cli", "inspect", str(path),
                           "--part", "nope"], capture_output=True, text=True)
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1 and "Traceback" not in proc.stderr
    assert "no element with id 'nope'" in lines[0]


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(["path", "rect", "circle", "ellipse", "polygon", "polyline", "use", "g"]),
       st.text(alphabet="MmLlAaQqCcSsTtZz0123456789.-, e#", max_size=40),
       st.text(alphabet="0123456789.-e%mx", max_size=6),
       st.sampled_from(["", "scale(0)", "skewX(90)", "matrix(1 2 3 4 5 6)", "rotate(",
                        "translate(1e308, 0) scale(1e308)"]))
def test_random_svg_only_raises_input_error(tag, d, length, transform):
    attributes = (f'd="{d}" points="{d}" href="{d}" width="{length}" height="{length}" '
                  f'r="{length}" rx="{length}" ry="{length}" transform="{transform}"')
    try:
        p = polygon_from_svg(f'<svg {SVG_NS}><{tag} {attributes}/><defs><path id="0" '
                             f'd="{d}"/></defs></svg>', "fuzz")
    except InputError as e:
        assert "\n" not in str(e)
    else:
        assert p.area > 0 and p.to_shapely().is_valid


def test_strokes_and_invisible_shapes_are_said_not_guessed():
    """A stroked rectangle is read as its fill (10 x 10, exactly) with a warning that a
    browser paints half the 4-wide stroke outside it; a shape with opacity 0 or a
    transparent fill is never the object, however large, and the polygon says so."""
    stroked = polygon_from_svg('<svg><rect width="10" height="10" '
                               'style="fill:#ccc;stroke:#000;stroke-width:4"/></svg>')
    assert stroked.area == 100.0
    assert any("stroke 4 wide" in w for w in stroked.warnings)
    for hidden in ('opacity="0"', 'fill="transparent"', 'fill-opacity="0%"'):
        p = polygon_from_svg(f'<svg><rect width="10" height="10" {hidden}/>'
                             '<rect x="20" width="2" height="3"/></svg>')
        assert p.area == 6.0, hidden
        assert p.warnings


@pytest.mark.parametrize("tolerance", [1e-2, 1e-4, 1e-6])
def test_a_stated_tolerance_bounds_the_chords_of_a_circle(tolerance):
    """tolerance= is kept: every chord of a circle of radius 2 (size: its diagonal, 4√2)
    lies within tolerance × size of the circle (closed form: a chord spanning an angle θ
    sags r(1 - cos θ/2) at its middle), its vertices lie on the circle, and a smaller
    tolerance gives more chords."""
    import math

    p = polygon_from_svg('<svg><circle r="2"/></svg>', tolerance=tolerance)
    ring = p.outer
    np.testing.assert_allclose(np.linalg.norm(ring, axis=1), 2.0, rtol=1e-12)
    mid = (ring + np.roll(ring, -1, axis=0)) / 2
    assert np.max(2.0 - np.linalg.norm(mid, axis=1)) <= tolerance * 4 * math.sqrt(2)
    assert f"({tolerance:g} of the shape's size)" in p.warnings[0]


@pytest.mark.parametrize("bad", [0, -1e-3, 0.5, float("nan"), "1e-3"])
def test_a_tolerance_out_of_range_is_refused(bad):
    with pytest.raises(InputError, match="tolerance must be"):
        polygon_from_svg('<svg><circle r="2"/></svg>', tolerance=bad)
