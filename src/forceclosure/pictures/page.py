"""Smaller offline pages: a plotly figure and plotly.js, packed in one HTML file or shared.

plotly's own offline page inlines the whole of plotly.js (4.8 MB) as text,
which is almost all of a page's size: a page of ten grasps on a duck held
32 kB of figure. :func:`small_page` inlines the same plotly.js, the one the
installed plotly (Python) ships and writes figures for, gzip-compressed and
base64-encoded (about 2 MB), and has the browser unpack it
(``DecompressionStream``: Chrome and Edge 80, Firefox 113, Safari 16.4 and
later) before drawing. Nothing is fetched: the page works from a file,
offline. The figure itself is written as plotly writes it
(``Plotly.newPlot("fc-figure", data, layout, config)``, numbers as base64
typed arrays).

Where many pages are written (``dataset --gripper --html DIR``, ``grasps
--html-shared``), each page loads one plotly.js file beside it instead,
``<script src="plotly.min.js">`` (:func:`small_page` with ``plotly_js``;
:func:`write_plotly_js` writes that file, the installed plotly's, once): a
page is then only its figure (tens of kB; under 1 MB) and the folder works
from files, offline, as long as the pages and ``plotly.min.js`` stay
together. This package does not carry a copy of plotly.js's 3-D partial
bundle, which no Python package ships.
"""

from __future__ import annotations

import base64
import functools
import html
import json
import re

from ..extras import require

__all__ = ["PLOTLY_JS", "small_page", "write_plotly_js"]

#: The shared plotly.js file's name, beside the pages that load it.
PLOTLY_JS = "plotly.min.js"

_LOADER = """(async function () {
  var div = document.getElementById("fc-figure");
  if (typeof DecompressionStream === "undefined") {
    div.textContent = "This page unpacks its plotting library with DecompressionStream, "
      + "which this browser lacks: open it in Chrome or Edge 80, Firefox 113, Safari 16.4 "
      + "or later.";
    return;
  }
  var packed = document.getElementById("fc-plotly").textContent;
  var bytes = Uint8Array.from(atob(packed), function (c) { return c.charCodeAt(0); });
  var stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("gzip"));
  (0, eval)(await new Response(stream).text());
  Plotly.newPlot("fc-figure", %(data)s, %(layout)s, %(config)s);
})();"""

_SHARED = """(function () {
  var div = document.getElementById("fc-figure");
  if (typeof Plotly === "undefined") {
    div.textContent = %(missing)s;
    return;
  }
  Plotly.newPlot("fc-figure", %(data)s, %(layout)s, %(config)s);
})();"""


@functools.cache
def _packed() -> str:
    """The installed plotly's plotly.js, gzip-compressed and base64-encoded (once a
    process)."""
    import gzip

    offline = require("plotly.offline", "the interactive HTML view", "view")
    packed = gzip.compress(offline.get_plotlyjs().encode("utf-8"), 9, mtime=0)
    return base64.b64encode(packed).decode("ascii")


def _json(value) -> str:
    """JSON safe inside a ``<script>`` element."""
    return json.dumps(value, separators=(",", ":")).replace("</", "<\\/")


def _relative_src(name: str) -> str:
    """``name`` as a ``src`` attribute: a relative file name, refused otherwise."""
    from urllib.parse import quote

    from ..errors import InputError

    text = str(name)
    if (not text or text.startswith(("/", "\\")) or "\\" in text or ":" in text
            or any(ord(c) < 32 for c in text) or text.endswith("/")):
        raise InputError(f"plotly_js {text!r}: give a file name relative to the page, "
                         f"such as {PLOTLY_JS!r}")
    return html.escape(quote(text, safe="/"), quote=True)


def small_page(fig, title: str = "forceclosure", config: dict | None = None,
               plotly_js: str | None = None) -> str:
    """The HTML of one offline page drawing the plotly figure ``fig``: self-contained, or
    loading a plotly.js file beside it.

    Parameters
    ----------
    fig : plotly.graph_objects.Figure
    title : str
        The page's title (markup is dropped).
    config : dict, optional
        plotly.js's config; default: no logo, responsive.
    plotly_js : str, optional
        None (default): the installed plotly's plotly.js is inlined, packed (about 2 MB;
        the page is one file). A file name relative to the page (such as
        :data:`PLOTLY_JS`, written by :func:`write_plotly_js`): the page loads it with
        ``<script src=...>`` (from ``file://`` too, offline) and holds only the figure.
        The figure is drawn by the same ``Plotly.newPlot`` call either way.

    Returns
    -------
    str

    Raises
    ------
    InputError
        ``plotly_js`` is not a relative file name (an absolute path, a URL, empty).

    References
    ----------
    Not from the paper: the offline view of its regions and grasps
    (:mod:`forceclosure.pictures.view`).

    Examples
    --------
    >>> import plotly.graph_objects as go
    >>> fig = go.Figure(go.Scatter3d(x=[0, 1], y=[0, 1], z=[0, 1]))
    >>> page = small_page(fig)
    >>> 1_000_000 < len(page) < 2_500_000, "<script src=" in page
    (True, False)
    >>> shared = small_page(fig, plotly_js="plotly.min.js")
    >>> len(shared) < 10_000, '<script src="plotly.min.js"></script>' in shared
    (True, True)
    """
    plotly_io = require("plotly.io", "the interactive HTML view", "view")
    src = None if plotly_js is None else _relative_src(plotly_js)
    figure = json.loads(plotly_io.to_json(fig, validate=False))
    text = re.sub(r"<[^>]*>", " ", str(title))
    parts = {"data": _json(figure.get("data", [])),
             "layout": _json(figure.get("layout", {})),
             "config": _json(config or {"displaylogo": False, "responsive": True})}
    head = ("<!DOCTYPE html>\n<html>\n<head><meta charset=\"utf-8\">"
            f"<title>{html.escape(' '.join(text.split()))}</title></head>\n"
            "<body style=\"margin:0\">\n"
            "<div id=\"fc-figure\" style=\"width:100%;height:100vh\"></div>\n")
    if src is None:
        library = (f"<script id=\"fc-plotly\" type=\"application/octet-stream\">{_packed()}"
                   "</script>\n")
        script = _LOADER % parts
    else:
        library = f"<script src=\"{src}\"></script>\n"
        script = _SHARED % {**parts, "missing": _json(
            f"This page draws with {plotly_js}, which did not load: keep the page and "
            f"{plotly_js} together, as they were written.")}
    return f"{head}{library}<script>\n{script}\n</script>\n</body>\n</html>\n"


def write_plotly_js(folder, name: str = PLOTLY_JS):
    """Write the installed plotly's plotly.js into ``folder`` as ``name`` (atomically), for
    the pages there that load it (:func:`small_page` with ``plotly_js=name``); a file of the
    same content already there is left as it is. Returns its path.

    Another plotly.js under that name (from another plotly version) is replaced: the pages
    written now are plotly's figures for the installed version.

    Parameters
    ----------
    folder : str or Path
        An existing folder.
    name : str
        The file's name (default :data:`PLOTLY_JS`).

    Returns
    -------
    Path

    Raises
    ------
    OutputError
        The file cannot be written (a missing or read-only folder, a full disk).

    References
    ----------
    Not from the paper: the offline view of its regions and grasps.

    Examples
    --------
    >>> import tempfile, plotly.offline
    >>> path = write_plotly_js(tempfile.mkdtemp())
    >>> path.name, path.read_text(encoding="utf-8") == plotly.offline.get_plotlyjs()
    ('plotly.min.js', True)
    >>> inode = path.stat().st_ino
    >>> write_plotly_js(path.parent).stat().st_ino == inode  # the same file: not rewritten
    True
    """
    from pathlib import Path

    from ..files.atomic import atomic_write

    path = Path(folder) / name
    content = _plotly_js()
    try:
        same = path.is_file() and path.stat().st_size == len(content) \
            and path.read_bytes() == content
    except OSError:
        same = False
    if not same:
        with atomic_write(str(path)) as f:
            f.write(content)
    return path


@functools.cache
def _plotly_js() -> bytes:
    """The installed plotly's plotly.js, as UTF-8 (once a process)."""
    offline = require("plotly.offline", "the interactive HTML view", "view")
    return offline.get_plotlyjs().encode("utf-8")
