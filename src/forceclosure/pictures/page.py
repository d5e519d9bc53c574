"""Small offline pages: a plotly figure and plotly.js's 3-D bundle in one HTML file under 1 MB.

plotly's own offline page inlines the whole of plotly.js (4.8 MB), which is
almost all of a page's size: a page of ten grasps on a duck held 32 kB of
figure. :func:`small_page` inlines instead plotly.js's ``gl3d`` partial
bundle (the same plotly.js version as the installed plotly's, with the 3-D
traces ``scatter3d`` and ``mesh3d`` and the sliders and menus: 1.75 MB),
gzip-compressed (556 kB, :data:`BUNDLE`, shipped with the package under
its MIT licence) and base64-encoded, and has the browser unpack it
(``DecompressionStream``: Chrome and Edge 80, Firefox 113, Safari 16.4 and
later) before drawing. Nothing is fetched: the page works from a file,
offline. The figure itself is written as plotly writes it
(``Plotly.newPlot("fc-figure", data, layout, config)``, numbers as base64
typed arrays).
"""

from __future__ import annotations

import base64
import functools
import html
import json
import re
from pathlib import Path

__all__ = ["BUNDLE", "BUNDLE_VERSION", "small_page"]

#: plotly.js's gl3d partial bundle, gzip-compressed (npm's ``plotly.js-gl3d-dist-min``).
BUNDLE = Path(__file__).with_name("vendor") / "plotly-gl3d.min.js.gz"

#: Its plotly.js version: the one the installed plotly (Python) writes figures for.
BUNDLE_VERSION = "4.1.1"

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
    return base64.b64encode(BUNDLE.read_bytes()).decode("ascii")


def _json(value) -> str:
    """JSON safe inside a ``<script>`` element."""
    return json.dumps(value, separators=(",", ":")).replace("</", "<\\/")


def small_page(fig, title: str = "forceclosure", config: dict | None = None) -> str:
    """The HTML of one self-contained, offline page drawing the plotly figure ``fig``.

    Parameters
    ----------
    fig : plotly.graph_objects.Figure
        Of the traces the gl3d bundle draws (``scatter3d``, ``mesh3d``, ...).
    title : str
        The page's title (markup is dropped).
    config : dict, optional
        plotly.js's config; default: no logo, responsive.

    Examples
    --------
    >>> import plotly.graph_objects as go
    >>> page = small_page(go.Figure(go.Scatter3d(x=[0, 1], y=[0, 1], z=[0, 1])))
    >>> 500_000 < len(page) < 1_000_000, "<script src=" in page
    (True, False)
    """
    import plotly.io

    figure = json.loads(plotly.io.to_json(fig, validate=False))
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
