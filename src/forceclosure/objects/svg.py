"""Reading a polygon from an SVG file as a browser draws it.

The file is parsed with svgelements, which applies what a browser applies:
transforms on groups and elements (nested), ``<use>`` (``href`` or
``xlink:href``, with its ``x``/``y``), the ``viewBox`` and length units (mm,
in, pt... at 96 px per inch), CSS ``style`` attributes and ``<style>``
sheets, and ``display: none``. What is never drawn is ignored: the content
of ``<defs>``, ``<symbol>`` (unless a ``<use>`` draws it), ``<clipPath>``,
``<mask>``, ``<marker>`` and ``<pattern>``, hidden elements
(``visibility: hidden``), and ``<line>``, which encloses no area.

Geometry:

* **coordinates** are the root ``<svg>``'s user units: its viewBox units
  when it has one (a file with ``width="100mm" viewBox="0 0 100 50"`` is
  read in millimetres), else CSS px;
* **units**: the polygon's ``units`` says what one of its coordinates measures, from the
  root's ``width``/``height`` over its viewBox (:func:`svg_units`): ``"mm"`` for a
  drawing at one millimetre per user unit (as Inkscape writes), ``"0.5 mm"`` when one
  unit is half a millimetre, ``"px"`` (CSS px, 1/96 in) without a viewBox, and ``None``
  when the file does not say (a viewBox without ``width``/``height``, or sizes in ``%``
  or ``em``);
* **y is up**: the drawing is read as seen, in a right-handed frame. With a
  root viewBox ``(x0, y0, w, h)``, a point drawn at ``(x, y)`` is read as
  ``(x - x0, y0 + h - y)``: the origin is the bottom-left corner of the
  viewBox. Without a viewBox it is read as ``(x, -y)``;
* **straight segments are exact**; curves (arcs, quadratic and cubic
  Béziers, the corners of rounded ``<rect>``, ``<circle>``, ``<ellipse>``)
  are cut into chords that stay within :data:`SVG_TOLERANCE` times the
  shape's size (its bounding-box diagonal) of the true curve, and the
  polygon's ``warnings`` say so. For a curve ``p(s)``, ``s`` in ``[0, 1]``,
  ``n`` equal steps in ``s`` keep every chord within ``max|p''| / (8 n²)``
  of the curve, and ``n`` is the smallest that makes this at most the
  tolerance;
* **one shape** (``<path>``, ``<polygon>``, ``<polyline>``, ``<rect>``,
  ``<circle>``, ``<ellipse>``) is the object. Its subpaths' largest ring is
  the outer boundary and the others are holes, where the fill rule leaves
  them unfilled; a subpath outside the outer boundary (a second island) is
  refused. An open subpath is closed, as a fill is. A shape with no fill
  but a stroke is read as the region its closed outline encloses; an open
  stroke encloses nothing and is refused;
* **several shapes**: the largest by area is read, with a warning naming
  the others; ``part`` picks one by its ``id`` (or the ``id`` of a group or
  ``<use>`` around it).

Every failure is an :class:`~forceclosure.errors.InputError` of one line
naming the element, e.g. ``<path id="x">``, or ``<rect> #2`` (the second
drawn ``<rect>``) when it has no id.
"""

from __future__ import annotations

import io
import math
import re
import xml.etree.ElementTree as ET
from collections import Counter
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import shapely
import svgelements as se
from numpy.typing import NDArray

from ..errors import InputError, first_line
from ..geometry.rings import signed_area
from .polygon import RTOL, Polygon

__all__ = ["MAX_DEPTH", "SVG_TOLERANCE", "polygon_from_svg", "svg_units"]

#: Largest distance between a curve and the chords that replace it, relative to the
#: shape's size (the diagonal of its bounding box).
SVG_TOLERANCE = 1e-3

#: Most chords per curve segment; more means a degenerate curve.
MAX_PIECES = 100_000

#: Deepest nesting of elements read (drawings nest groups a few tens deep; the reader
#: and svgelements walk the tree recursively, within Python's recursion limit).
MAX_DEPTH = 200

_XLINK = "{http://www.w3.org/1999/xlink}href"
#: Referenced only: svgelements would draw their content where they stand.
_ONLY_REFERENCED = ("symbol", "mask", "marker")
_SHAPES = (se.Path, se.Rect, se.Ellipse, se.Circle, se.Polyline, se.Polygon)
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_PATH_COMMANDS = "MmZzLlHhVvCcSsQqTtAa"
#: svgelements takes 0.0393701 in per mm (5e-7 off); mm and cm are converted here exactly.
_METRIC = {"mm": 96 / 25.4, "cm": 96 / 2.54}
_LENGTH_ATTRIBUTES = ("x", "y", "width", "height", "rx", "ry", "cx", "cy", "r", "x1", "y1",
                      "x2", "y2")


#: CSS absolute lengths in px (96 px per inch).
_CSS_UNITS = {"px": 1.0, "in": 96.0, "cm": 96 / 2.54, "mm": 96 / 25.4, "pt": 96 / 72,
              "pc": 16.0, "Q": 96 / 101.6}


def _length(value: str | None) -> tuple[float, str] | None:
    """``width="100mm"`` as ``(100.0, "mm")``; a bare number is px; ``None`` for a missing,
    relative (``%``, ``em``, ``ex``...) or non-positive length."""
    if value is None:
        return None
    match = re.fullmatch(rf"\s*({_NUMBER})\s*([A-Za-z%]*)\s*", value)
    if not match:
        return None
    number, unit = float(match[1]), match[2] or "px"
    if unit not in _CSS_UNITS or not (math.isfinite(number) and number > 0):
        return None
    return number, unit


def svg_units(root: ET.Element) -> str | None:
    """What one user unit of the root ``<svg>`` measures, as the file states it.

    Parameters
    ----------
    root : xml.etree.ElementTree.Element
        The root ``<svg>`` element, as written (before any lengths are converted).

    Returns
    -------
    str or None
        ``"mm"`` (or ``"pt"``, ``"in"``, ``"px"``...) when one user unit is one of that
        unit, ``"0.5 mm"`` when it is a multiple of it (the unit of ``width``, else of
        ``height``), ``"px"`` (CSS px, 1/96 in) without a viewBox, and ``None`` when the
        file does not say: a viewBox with neither ``width`` nor ``height`` in absolute
        units, or with ``preserveAspectRatio="none"`` stretching x and y differently.

    Examples
    --------
    >>> svg_units(ET.fromstring('<svg width="210mm" height="297mm" viewBox="0 0 210 297"/>'))
    'mm'
    >>> svg_units(ET.fromstring('<svg width="100mm" viewBox="0 0 200 50"/>'))
    '0.5 mm'
    >>> svg_units(ET.fromstring('<svg viewBox="0 0 4 4"/>')) is None
    True
    >>> svg_units(ET.fromstring('<svg width="3in"/>'))
    'px'
    """
    values = re.findall(_NUMBER, root.get("viewBox", ""))
    if not (len(values) == 4 and float(values[2]) > 0 and float(values[3]) > 0):
        return "px"  # user units are CSS px (lengths in mm are converted to them)
    box = (float(values[2]), float(values[3]))
    sizes = [_length(root.get(k)) for k in ("width", "height")]
    scales = [s[0] * _CSS_UNITS[s[1]] / b for s, b in zip(sizes, box, strict=True) if s]
    if not scales:
        return None
    if (len(scales) == 2 and not math.isclose(scales[0], scales[1], rel_tol=1e-9)
            and root.get("preserveAspectRatio", "").strip().startswith("none")):
        return None  # x and y stretched differently: no one unit
    scale = min(scales)  # the default "meet": the smaller scale fits both
    unit = next(s[1] for s in sizes if s)
    factor = scale / _CSS_UNITS[unit]
    if math.isclose(factor, 1.0, rel_tol=1e-9):
        return unit
    return f"{factor:.6g} {unit}"


def _depth(root: ET.Element) -> int:
    """How deep elements nest below ``root`` (1 for a lone root), without recursion."""
    deepest, level = 1, [root]
    while True:
        level = [child for element in level for child in element]
        if not level:
            return deepest
        deepest += 1


def _local(tag: Any) -> str:
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


def _xml_label(element: ET.Element) -> str:
    tag, ident = _local(element.tag), element.get("id")
    return f'<{tag} id="{ident}">' if ident else f"<{tag}>"


def _check_path_data(d: str, where: str) -> None:
    """Refuse path data a browser would stop drawing at, naming the place."""
    if not d.strip():
        return
    if d.lstrip()[0] not in "Mm":
        raise InputError(f"{where}: path data must start with a move (M)")
    lexer = se.SVGLexicalParser()
    path = se.Path()
    try:
        lexer.parse(path, d)
        bad = lexer.pos < len(d) and d[lexer.pos:].strip() != ""
        if not bad:
            for seg in path:
                for point in (getattr(seg, k, None) for k in ("start", "end", "control",
                                                              "control1", "control2")):
                    if point is not None and (point.x is None or point.y is None):
                        bad = True
    except Exception:  # svgelements raises bare ValueError (and TypeError) on bad data
        bad = True
    if not bad:
        return
    commands = [c for c in d[:lexer.pos] if c in _PATH_COMMANDS]
    command = commands[-1] if commands else "M"
    what = ("takes no numbers" if command in "Zz" else "has missing or bad numbers")
    near = d[lexer.pos:lexer.pos + 12].strip()
    if near and near[0].isalpha() and near[0] not in _PATH_COMMANDS + "eE":
        raise InputError(f"{where}: unknown path command '{near[0]}' (at character "
                         f"{d.index(near[0], lexer.pos) + 1})")
    raise InputError(f"{where}: path command '{command}' {what} (at character {lexer.pos + 1}"
                     + (f", '{near}')" if near else ", the end)"))


def _prepare(root: ET.Element, name: str) -> float | None:
    """Check the XML tree and adjust it for svgelements; the viewBox's height, if any."""
    if _local(root.tag) != "svg":
        raise InputError(f"{name}: not an SVG file: the root element is <{_local(root.tag)}>")
    namespace = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    ids = {el.get("id"): el for el in root.iter() if el.get("id")}
    parents = {child: parent for parent in root.iter() for child in parent}
    for element in root.iter():
        tag = _local(element.tag)
        where = f"{name}: {_xml_label(element)}"
        for attribute in _LENGTH_ATTRIBUTES:
            metric = re.fullmatch(rf"\s*({_NUMBER})\s*(mm|cm)\s*", element.get(attribute, ""))
            if metric:
                element.set(attribute, repr(float(metric[1]) * _METRIC[metric[2]]))
        if tag == "path":
            _check_path_data(element.get("d", ""), where)
        elif tag in ("polygon", "polyline"):
            points = element.get("points", "")
            values = re.findall(_NUMBER, points)
            if len(values) % 2:
                raise InputError(f"{where}: odd number of coordinates in 'points'")
            if re.sub(_NUMBER, "", points).strip(" \t\r\n,"):
                raise InputError(f"{where}: 'points' holds something other than numbers")
        elif tag == "use":
            ref = element.get(_XLINK) or element.get("href") or ""
            target = ids.get(ref[1:]) if ref.startswith("#") else None
            if target is not None and _local(target.tag) == "symbol" and target.get("viewBox"):
                raise InputError(f"{where}: draws <symbol id=\"{ref[1:]}\"> with a viewBox, "
                                 "which is not read; draw the symbol's shapes directly")
    for element in list(root.iter()):
        if _local(element.tag) in _ONLY_REFERENCED and element in parents:
            parent = parents[element]
            index = list(parent).index(element)
            parent.remove(element)
            defs = ET.Element(f"{namespace}defs")
            defs.append(element)
            parent.insert(index, defs)
    _explicit_positions(root, namespace, name)
    values = re.findall(_NUMBER, root.get("viewBox", ""))
    if len(values) == 4 and float(values[2]) > 0 and float(values[3]) > 0:
        for attribute in ("width", "height"):  # read in viewBox units: no viewport scaling
            root.attrib.pop(attribute, None)
        return float(values[3])
    return None


def _explicit_positions(root: ET.Element, namespace: str, name: str) -> None:
    """Write out the defaults svgelements would otherwise inherit from an enclosing element.

    svgelements passes every attribute down to the children, so a ``<rect>`` without
    ``x`` inside ``<svg x="10">`` would take that 10; browsers take 0. A nested ``<svg>``
    without a viewBox is not moved to its ``x``, ``y`` by svgelements: a group does it.
    """
    defaults = {"rect": {"x": "0", "y": "0", "width": "0", "height": "0"},
                "use": {"x": "0", "y": "0"}, "image": {"x": "0", "y": "0"},
                "circle": {"cx": "0", "cy": "0"}, "ellipse": {"cx": "0", "cy": "0"},
                "svg": {"x": "0", "y": "0", "width": "100%", "height": "100%"}}
    parents = {child: parent for parent in root.iter() for child in parent}
    for element in list(root.iter()):
        tag = _local(element.tag)
        if element is root:
            continue
        if tag == "svg" and not element.get("viewBox") and (element.get("x") or element.get("y")):
            try:
                x, y = (float(element.get(k, "0")) for k in ("x", "y"))
            except ValueError:
                raise InputError(f"{name}: {_xml_label(element)}: a nested <svg> without a "
                                 "viewBox is read only with x and y in user units") from None
            parent = parents[element]
            index = list(parent).index(element)
            parent.remove(element)
            group = ET.Element(f"{namespace}g", {"transform": f"translate({x!r}, {y!r})"})
            group.append(element)
            parent.insert(index, group)
            element.set("x", "0")
            element.set("y", "0")
        for key, value in defaults.get(tag, {}).items():
            if element.get(key) is None:
                element.set(key, value)


def _matrix(m: se.Matrix) -> NDArray[np.float64]:
    return np.array([[m.a, m.c, m.e], [m.b, m.d, m.f], [0.0, 0.0, 1.0]])


def _pieces(bound: float, tol: float | None, where: str) -> int:
    """Equal steps that keep chords within ``tol`` of a curve with ``max|p''| <= bound``."""
    if tol is None:
        return 8
    if bound <= 0:
        return 1
    n = math.sqrt(bound / (8 * tol)) if tol > 0 else math.inf
    if not n <= MAX_PIECES:
        raise InputError(f"{where}: a curve would need more than {MAX_PIECES} chords to stay "
                         f"within {tol:.3g} of the true curve")
    return max(1, math.ceil(n))


#: Tangents sampled inside each chord to bound how far the curve turns from it.
TURN_SAMPLES = 16


def _turn(chord_ends: NDArray[np.float64], tangents: NDArray[np.float64]) -> float:
    """How far (radians) a curve's direction strays from its chords: ``chord_ends`` (n + 1, 2)
    and tangents (n, TURN_SAMPLES + 1, 2) sampled along each chord, ends included. The largest
    angle seen, plus the largest between neighbouring samples (what lies between them)."""
    def angle(a, b):
        cross = np.abs(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])
        norms = np.linalg.norm(a, axis=-1) * np.linalg.norm(b, axis=-1)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.arcsin(np.clip(cross / norms, 0.0, 1.0))

    chords = np.diff(chord_ends, axis=0)[:, None, :]
    seen = np.nanmax(angle(tangents, chords), initial=0.0)
    between = np.nanmax(angle(tangents[:, 1:], tangents[:, :-1]), initial=0.0)
    return float(seen + between)


def _bezier(ctrl: NDArray[np.float64], tol: float | None,
            where: str) -> tuple[NDArray[np.float64], float]:
    """Points along a Bézier curve (after its start), and how far it turns from its chords."""
    second = np.diff(ctrl, 2, axis=0)  # p'' is a blend of these, times deg (deg - 1)
    degree = len(ctrl) - 1
    bound = degree * (degree - 1) * float(np.linalg.norm(second, axis=1).max())
    n = _pieces(bound, tol, where)

    def at(s):
        if degree == 2:
            return (1 - s) ** 2 * ctrl[0] + 2 * (1 - s) * s * ctrl[1] + s ** 2 * ctrl[2]
        return ((1 - s) ** 3 * ctrl[0] + 3 * (1 - s) ** 2 * s * ctrl[1]
                + 3 * (1 - s) * s ** 2 * ctrl[2] + s ** 3 * ctrl[3])

    def tangent(s):
        first = np.diff(ctrl, axis=0)
        if degree == 2:
            return (1 - s) * first[0] + s * first[1]
        return (1 - s) ** 2 * first[0] + 2 * (1 - s) * s * first[1] + s ** 2 * first[2]

    pts = at(np.arange(1, n + 1)[:, None] / n)
    pts[-1] = ctrl[-1]
    fine = (np.arange(n)[:, None] + np.linspace(0, 1, TURN_SAMPLES + 1)[None]) / n
    turn = _turn(np.vstack([ctrl[:1], pts]), tangent(fine[..., None]))
    return pts, turn


def _arc(seg: se.Arc, transform: NDArray[np.float64], tol: float | None,
         where: str) -> tuple[NDArray[np.float64], float | None]:
    """Points along an elliptical arc (after its start), and how far it turns from its
    chords (None: a straight line).

    The ellipse is ``c + u cos t + v sin t`` with ``u``, ``v`` the conjugate radii
    svgelements keeps (``prx``, ``pry``), which any affine map carries along, so
    skewed arcs stay exact.
    """
    def xy(p: se.Point) -> NDArray[np.float64]:
        return np.array([float(p.x), float(p.y)])

    linear, shift = transform[:2, :2], transform[:2, 2]
    end = linear @ xy(seg.end) + shift
    c = xy(seg.center)
    u, v = xy(seg.prx) - c, xy(seg.pry) - c
    s0, s1 = xy(seg.start), xy(seg.end)
    det = u[0] * v[1] - u[1] * v[0]
    scale = float(np.linalg.norm(u) + np.linalg.norm(v))
    sweep = float(seg.sweep)
    if sweep == 0 or abs(det) <= 1e-12 * scale ** 2:  # a zero radius: a straight line
        return end[None, :], None
    if det < 0:  # svgelements flips the sweep of mirrored arcs; t runs with (u, v)
        sweep = -sweep
    cos_sin = np.linalg.solve(np.column_stack([u, v]), s0 - c)
    t0 = math.atan2(cos_sin[1], cos_sin[0])
    for angle, p in ((t0, s0), (t0 + sweep, s1)):
        if np.linalg.norm(c + u * math.cos(angle) + v * math.sin(angle) - p) > 1e-6 * scale:
            raise InputError(f"{where}: cannot read an arc exactly (its ends are off its "
                             "ellipse)")
    uu, vv, cc = linear @ u, linear @ v, linear @ c + shift
    bound = sweep ** 2 * float(np.linalg.norm(np.column_stack([uu, vv]), 2))
    n = _pieces(bound, tol, where)
    t = t0 + sweep * np.arange(1, n + 1)[:, None] / n
    pts = cc + np.cos(t) * uu + np.sin(t) * vv
    pts[-1] = end
    fine = t0 + sweep * (np.arange(n)[:, None] + np.linspace(0, 1, TURN_SAMPLES + 1)[None]) / n
    tangents = sweep * (-np.sin(fine)[..., None] * uu + np.cos(fine)[..., None] * vv)
    start = cc + math.cos(t0) * uu + math.sin(t0) * vv
    return pts, _turn(np.vstack([start, pts]), tangents)


@dataclass
class _Drawn:
    """One drawn shape: where it came from, and its subpaths in root user units."""

    element: Any
    ancestors: list[Any]
    tag: str
    label: str
    filled: bool
    stroked: bool
    evenodd: bool
    stroke_width: float = 0.0

    @property
    def ids(self) -> list[str]:
        return [str(n.values["id"]) for n in [*self.ancestors, self.element]
                if n.values.get("id")]

    def rings(self, tol: float | None,
              where: str) -> tuple[list[NDArray[np.float64]], list[bool], float | None]:
        """The subpaths as point arrays, whether each was closed, and how far the curves
        turn from their chords (None: no curves)."""
        with np.errstate(all="ignore"):  # overflow to inf is refused as not finite
            return self._rings(tol, where)

    def _rings(self, tol: float | None,
               where: str) -> tuple[list[NDArray[np.float64]], list[bool], float | None]:
        transform = _matrix(self.element.transform)
        linear, shift = transform[:2, :2], transform[:2, 2]
        rings: list[NDArray[np.float64]] = []
        closed: list[bool] = []
        curved: float | None = None
        current: list[NDArray[np.float64]] | None = None
        start = None

        def finish(is_closed: bool) -> None:
            if current is not None:
                rings.append(np.vstack(current))
                closed.append(is_closed)

        for seg in self.element.segments(transformed=False):
            if isinstance(seg, se.Move):
                finish(False)
                start = linear @ np.array([float(seg.end.x), float(seg.end.y)]) + shift
                current = [start[None, :]]
                continue
            if start is None:
                raise InputError(f"{where}: the path does not start with a move")
            if current is None:  # drawing on after a close starts at the closed subpath's start
                current = [start[None, :]]
            if isinstance(seg, se.Close):
                finish(True)
                current = None
                continue
            last = current[-1][-1]
            end = linear @ np.array([float(seg.end.x), float(seg.end.y)]) + shift
            if not (np.all(np.isfinite(end)) and np.all(np.isfinite(last))):
                raise InputError(f"{where}: a coordinate is not finite")
            if isinstance(seg, se.Line):
                current.append(end[None, :])
            elif isinstance(seg, se.QuadraticBezier | se.CubicBezier):
                inner = (seg.control,) if isinstance(seg, se.QuadraticBezier) else (
                    seg.control1, seg.control2)
                ctrl = np.array([last, *(linear @ np.array([float(p.x), float(p.y)]) + shift
                                         for p in inner), end])
                points, turn = _bezier(ctrl, tol, where)
                current.append(points)
                if not np.allclose(np.diff(ctrl, 2, axis=0), 0):
                    curved = max(curved or 0.0, turn)
            elif isinstance(seg, se.Arc):
                points, arc_turn = _arc(seg, transform, tol, where)
                current.append(points)
                if arc_turn is not None:
                    curved = max(curved or 0.0, arc_turn)
            else:
                raise InputError(f"{where}: unknown path segment {type(seg).__name__}")
        finish(False)
        return rings, closed, curved


def _number(value: Any, default: float) -> float:
    """The leading number of a style value (``0``, ``0.5``, ``2px``, ``50%`` as 0.5)."""
    if value is None:
        return default
    match = re.match(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(%?)", str(value))
    if not match:
        return default
    number = float(match.group(1))
    return number / 100 if match.group(2) else number


def _attribute(node: Any, key: str) -> str | None:
    value = node.values.get(se.SVG_STRUCT_ATTRIB, {}).get(key)
    return None if value is None else str(value).strip()


def _collect(svg: se.SVG) -> tuple[list[_Drawn], Counter]:
    drawn: list[_Drawn] = []
    skipped: Counter = Counter()
    per_tag: Counter = Counter()

    def walk(node: Any, ancestors: list[Any]) -> None:
        for child in node:
            if isinstance(child, se.Group | se.Use):
                walk(child, [*ancestors, child])
                continue
            values = getattr(child, "values", {}) or {}
            if str(values.get("visibility", "visible")).strip().lower() in ("hidden",
                                                                            "collapse"):
                continue
            if isinstance(child, se.SimpleLine):
                skipped["<line>"] += 1
            elif isinstance(child, se.Text):
                skipped["<text>"] += 1
            elif isinstance(child, se.Image):
                skipped["<image>"] += 1
            elif isinstance(child, _SHAPES):
                tag = str(values.get("tag", type(child).__name__.lower()))
                per_tag[tag] += 1
                ident = values.get("id")
                label = f'<{tag} id="{ident}">' if ident else f"<{tag}> #{per_tag[tag]}"
                uses = [a for a in ancestors if isinstance(a, se.Use) and a.values.get("id")]
                if uses:
                    label += f' in <use id="{uses[-1].values["id"]}">'
                if _number(values.get("opacity"), 1.0) == 0:
                    skipped["invisible shape (opacity 0)"] += 1
                    continue
                fill = str(values.get("fill", "black")).strip().lower()
                filled = (fill not in ("none", "transparent")
                          and _number(values.get("fill-opacity"), 1.0) != 0)
                stroke = str(values.get("stroke", "none")).strip().lower()
                stroked = (stroke not in ("none", "", "transparent")
                           and _number(values.get("stroke-opacity"), 1.0) != 0)
                rule = str(values.get("fill-rule", "nonzero")).strip().lower()
                width = _number(values.get("stroke-width"), 1.0) if stroked else 0.0
                drawn.append(_Drawn(child, ancestors, tag, label, filled, stroked,
                                    rule == "evenodd", width))

    walk(svg, [svg])
    return drawn, skipped


@dataclass
class _Candidate:
    shape: _Drawn
    rings: list[NDArray[np.float64]]
    closed: list[bool]
    curved: float | None
    tol: float
    area: float
    relative: float


def _candidate(shape: _Drawn, name: str, tolerance: float) -> _Candidate | str:
    """The shape's subpaths at the stated tolerance, or why it encloses no region."""
    where = f"{name}: {shape.label}"
    try:
        coarse, _, _ = shape.rings(None, where)
        if not coarse:
            return "it draws nothing"
        points = np.vstack(coarse)
        if not np.all(np.isfinite(points)):
            raise InputError(f"{where}: a coordinate is not finite")
        size = float(np.linalg.norm(np.ptp(points, axis=0)))
        if size == 0:
            return "it is a single point"
        tol = tolerance * size
        rings, closed, curved = shape.rings(tol, where)
    except InputError:
        raise
    except (ValueError, TypeError, AttributeError, ZeroDivisionError, OverflowError,
            IndexError, np.linalg.LinAlgError) as e:  # svgelements on odd input
        raise InputError(f"{where}: cannot read its geometry: {first_line(e)}") from None
    if not shape.filled:
        if not shape.stroked:
            return "it has neither fill nor stroke"
        if not all(closed):
            return "it is an open stroke with no fill"
    kept = [r for r in rings if len(np.unique(r, axis=0)) >= 3]
    if not kept:
        return "it encloses no area"
    areas = sorted((abs(signed_area(r)) for r in kept), reverse=True)
    return _Candidate(shape, rings, closed, curved, tol, areas[0] - sum(areas[1:]), tolerance)


def _clip_check(svg: se.SVG, chosen: _Candidate, name: str) -> None:
    """Refuse a shape cut by a clip-path or mask: what is drawn is then not the shape."""
    shape = chosen.shape
    outer = max((r for r in chosen.rings if len(r) >= 3), key=lambda r: abs(signed_area(r)))
    region = shapely.Polygon(outer)
    for node in [*shape.ancestors, shape.element]:
        where = f"{name}: {shape.label}"
        if _attribute(node, "mask") not in (None, "none"):
            raise InputError(f"{where}: it is masked ({_attribute(node, 'mask')}); masks are "
                             "not read")
        url = _attribute(node, "clip-path")
        if url in (None, "none"):
            continue
        clip = svg.get_element_by_url(url)
        if not isinstance(clip, se.ClipPath):
            raise InputError(f"{where}: its clip-path {url} names no <clipPath>")
        if str(clip.values.get("clipPathUnits", "userSpaceOnUse")) != "userSpaceOnUse":
            raise InputError(f"{where}: its clip-path {url} is in objectBoundingBox units, "
                             "which are not read")
        # clip content is in the user space of the clipped element, not where it is defined
        try:
            fix = (_matrix(se.Matrix(node.values.get("transform", "")))
                   @ np.linalg.inv(_matrix(se.Matrix(clip.values.get("transform", "")))))
        except (np.linalg.LinAlgError, ValueError) as e:
            raise InputError(f"{where}: cannot place its clip-path {url}: "
                             f"{first_line(e)}") from None
        parts = []
        for child in clip:
            if isinstance(child, _SHAPES):
                drawn = _Drawn(child, [], "clip", "<clipPath>", True, False, False)
                for ring in drawn.rings(chosen.tol, f"{name}: <clipPath> of {shape.label}")[0]:
                    if len(ring) >= 3:
                        ring = ring @ fix[:2, :2].T + fix[:2, 2]
                        parts.append(shapely.make_valid(shapely.Polygon(ring)))
        area = shapely.unary_union(parts) if parts else shapely.Polygon()
        if not area.buffer(chosen.tol).covers(region):
            raise InputError(f"{where}: it is cut by its clip-path {url}; clipped shapes are "
                             "not read")


def _assemble(chosen: _Candidate, name: str, flip: float | None) -> Polygon:
    """The polygon of one shape: largest ring outer, holes where the fill leaves them empty."""
    shape = chosen.shape
    where = f"{name}: {shape.label}"
    rings = []
    for index, ring in enumerate(chosen.rings, start=1):
        ring = np.column_stack([ring[:, 0], (flip if flip is not None else 0.0) - ring[:, 1]])
        if len(np.unique(ring, axis=0)) < 3:
            continue  # a lone move or a back-and-forth line: no area is filled
        size = float(np.ptp(ring, axis=0).max())
        if len(ring) > 3 and np.linalg.norm(ring[-1] - ring[0]) <= RTOL * size:
            ring = ring[:-1]  # the closing point computed again along a curve
        rings.append((index, ring))
    warnings = []
    if chosen.curved is not None:
        warnings.append(f"curves tessellated into chords within {chosen.tol:.3g} of the true "
                        f"curve ({chosen.relative:g} of the shape's size), turning from them by "
                        f"up to {chosen.curved:.3g} rad (every proof narrows its cones by that)")
    if not shape.filled:
        warnings.append(f"{shape.label} has no fill, only a stroke: read as the region its "
                        "outline encloses")
    elif shape.stroke_width > 0:
        warnings.append(f"{shape.label} is drawn with a stroke {shape.stroke_width:g} wide: "
                        "read as its fill's outline, without the half of the stroke a browser "
                        "paints outside it")
    outer_at = max(range(len(rings)), key=lambda k: abs(signed_area(rings[k][1])))
    outer_index, outer = rings[outer_at]
    outer_poly = shapely.Polygon(outer)
    others = [(i, r) for k, (i, r) in enumerate(rings) if k != outer_at]
    polys = {i: shapely.Polygon(r) for i, r in others}
    holes = []
    for i, ring in others:
        inside = polys[i].representative_point() if polys[i].is_valid else shapely.Point(ring[0])
        if not outer_poly.covers(inside):
            raise InputError(f"{where}: subpath {i} lies outside the outer boundary (subpath "
                             f"{outer_index}): a second island; draw it as its own shape")
        host = [j for j, p in polys.items() if j != i and p.is_valid and p.covers(inside)
                and p.area > polys[i].area]
        if host:
            raise InputError(f"{where}: subpath {i} lies inside subpath {host[0]}, itself "
                             "inside the outer boundary: nested islands are not read")
        same_way = (signed_area(ring) > 0) == (signed_area(outer) > 0)
        if (not shape.evenodd and same_way and polys[i].is_valid
                and outer_poly.is_valid and outer_poly.contains(polys[i])):
            warnings.append(f"subpath {i} of {shape.label} winds like the outer boundary, so "
                            "fill-rule nonzero fills it: read as filled, not as a hole")
            continue
        holes.append(ring)
    polygon = Polygon.from_points(outer, holes, name=where, warnings=warnings,
                                  spread=chosen.curved or 0.0)
    return replace(polygon, name=name)


def polygon_from_svg(text: str, name: str = "polygon", part: str | None = None,
                     tolerance: float = SVG_TOLERANCE) -> Polygon:
    """A polygon from SVG text, read as a browser draws it, with y up.

    Parameters
    ----------
    text : str
        The SVG document.
    name : str
        The object's name, used in messages (the file's stem).
    part : str, optional
        The ``id`` of the element to read (a shape, or a group or ``<use>`` around
        it). Without it, the largest drawn shape is read.
    tolerance : float
        How far chords may stray from a curve, relative to the shape's size
        (its bounding-box diagonal); default :data:`SVG_TOLERANCE`.

    Returns
    -------
    Polygon
        In the root's user units, y up (see the module's description), with
        ``warnings`` saying what was approximated or left out and ``units`` what one
        user unit measures (:func:`svg_units`), when the file says.

    Examples
    --------
    >>> svg = '<svg><path d="M0 0 H4 V4 H0 Z M1 1 V3 H3 V1 Z"/></svg>'
    >>> p = polygon_from_svg(svg)
    >>> p.area, len(p.holes), p.bounds.tolist()
    (12.0, 1, [[0.0, -4.0], [4.0, 0.0]])
    >>> disk = polygon_from_svg('<svg viewBox="0 0 4 4"><circle cx="2" cy="2" r="2"/></svg>')
    >>> round(disk.area, 1), disk.warnings[0].startswith("curves tessellated")  # pi r^2 = 12.57
    (12.5, True)
    >>> fine = polygon_from_svg('<svg><circle r="2"/></svg>', tolerance=1e-6)
    >>> len(disk.outer), len(fine.outer), round(fine.area, 4), round(fine.spread, 4)
    (44, 1324, 12.5663, 0.0027)
    """
    if not (isinstance(tolerance, int | float) and 0 < tolerance <= 0.1):
        raise InputError(f"{name}: tolerance must be a number in (0, 0.1], relative to the "
                         f"shape's size; got {tolerance!r}")
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise InputError(f"{name}: not valid SVG/XML: {first_line(e)}") from None
    depth = _depth(root)
    if depth > MAX_DEPTH:
        raise InputError(f"{name}: elements nested {depth:,} deep; at most {MAX_DEPTH} levels "
                         "are read")
    units = svg_units(root) if _local(root.tag) == "svg" else None
    flip = _prepare(root, name)
    try:
        svg = se.SVG.parse(io.StringIO(ET.tostring(root, encoding="unicode")), reify=True,
                           on_error="raise")
    except InputError:
        raise
    except Exception as e:  # svgelements raises many types on odd documents
        raise InputError(f"{name}: cannot read the SVG: {first_line(e)}") from None
    if not isinstance(svg, se.SVG):
        raise InputError(f"{name}: the SVG draws nothing")
    drawn, skipped = _collect(svg)
    not_read = ", ".join(f"{n} {tag}" for tag, n in skipped.items())
    if part is not None:
        picked = [s for s in drawn if part in s.ids]
        if not picked:
            ids = list(dict.fromkeys(i for s in drawn for i in s.ids))
            if part in {el.get("id") for el in root.iter()}:
                raise InputError(f"{name}: element id '{part}' is not drawn (it is in <defs>, "
                                 "a <symbol>, <clipPath> or <mask>, hidden, or not a shape)")
            listed = ", ".join(ids[:20]) + (", ..." if len(ids) > 20 else "")
            raise InputError(f"{name}: no element with id '{part}'; the ids there are: "
                             + (listed or "none"))
        drawn = picked
    candidates: list[tuple[_Drawn, _Candidate]] = []
    refused: list[tuple[_Drawn, str]] = []  # with the reason
    for shape in drawn:
        found = _candidate(shape, name, tolerance)
        if isinstance(found, _Candidate):
            candidates.append((shape, found))
        else:
            refused.append((shape, found))
    if not candidates:
        if refused:
            shape, why = refused[0]
            raise InputError(f"{name}: {shape.label} encloses no region: {why}")
        extra = f" ({not_read} not read)" if not_read else ""
        raise InputError(f"{name}: no drawn shape (path, polygon, polyline, rect, circle, "
                         f"ellipse) in the SVG{extra}")
    order = sorted(range(len(candidates)), key=lambda k: -candidates[k][1].area)
    chosen = candidates[order[0]][1]
    _clip_check(svg, chosen, name)
    polygon = _assemble(chosen, name, flip)
    notes = []
    if len(candidates) > 1:
        others = [candidates[k][0].label for k in order[1:]]
        listed = ", ".join(others[:10]) + (", ..." if len(others) > 10 else "")
        notes.append(f"{len(candidates)} drawn shapes: read the largest, {chosen.shape.label}; "
                     f"ignored {listed} (pick one with part=ID / --part ID)")
    if refused:
        notes.append("ignored, enclosing no region: " + ", ".join(
            f"{shape.label} ({why})" for shape, why in refused[:5]))
    if not_read and part is None:
        notes.append(f"not read: {not_read}")
    return replace(polygon, warnings=(*polygon.warnings, *notes), units=units)
