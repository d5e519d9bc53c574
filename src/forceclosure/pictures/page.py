"""Smaller offline pages: a plotly figure and plotly.js, packed, in one HTML file.

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

A page under 1 MB would need plotly.js's 3-D partial bundle, which no
Python package ships; this package does not carry a copy of it.
"""

from __future__ import annotations

import base64
import functools
import html
import json
import re

from ..extras import require

__all__ = ["small_page"]

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


def small_page(fig, title: str = "forceclosure", config: dict | None = None) -> str:
    """The HTML of one self-contained, offline page drawing the plotly figure ``fig``.

    Parameters
    ----------
    fig : plotly.graph_objects.Figure
    title : str
        The page's title (markup is dropped).
    config : dict, optional
        plotly.js's config; default: no logo, responsive.

    Examples
    --------
    >>> import plotly.graph_objects as go
    >>> page = small_page(go.Figure(go.Scatter3d(x=[0, 1], y=[0, 1], z=[0, 1])))
    >>> 1_000_000 < len(page) < 2_500_000, "<script src=" in page
    (True, False)
    """
    plotly_io = require("plotly.io", "the interactive HTML view", "view")
    figure = json.loads(plotly_io.to_json(fig, validate=False))
    text = re.sub(r"<[^>]*>", " ", str(title))
    script = _LOADER % {"data": _json(figure.get("data", [])),
                        "layout": _json(figure.get("layout", {})),
                        "config": _json(config or {"displaylogo": False, "responsive": True})}
    return ("<!DOCTYPE html>\n<html>\n<head><meta charset=\"utf-8\">"
            f"<title>{html.escape(' '.join(text.split()))}</title></head>\n"
            "<body style=\"margin:0\">\n"
            "<div id=\"fc-figure\" style=\"width:100%;height:100vh\"></div>\n"
            f"<script id=\"fc-plotly\" type=\"application/octet-stream\">{_packed()}</script>\n"
            f"<script>\n{script}\n</script>\n</body>\n</html>\n")
