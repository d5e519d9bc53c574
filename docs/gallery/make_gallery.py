"""Regenerate the pictures of docs/gallery.md.

    uv run python docs/gallery/make_gallery.py
"""

from pathlib import Path

import pybullet_data

from forceclosure.objects import bundled, glyph
from forceclosure.objects.io import load_object
from forceclosure.pictures.plot import plot_object, plot_regions, plot_spatial_regions
from forceclosure.synthesis.best import synthesize

HERE = Path(__file__).parent


def main() -> None:
    pictures = {
        "wrench-head-two-fingers.png": lambda: plot_regions(
            synthesize(bundled("wrench-head"), 2, "hard", 0.3, top=3).found),
        "wrench-head-nguyen.png": lambda: plot_regions(
            synthesize(bundled("wrench-head"), 2, "hard", 0.3, top=3,
                       construction="nguyen").found),
        "triangle-three-fingers.png": lambda: plot_regions(
            synthesize(bundled("triangle"), 3, "hard", 0.3, top=1).found),
        "bracket-four-frictionless.png": lambda: plot_regions(
            synthesize(bundled("bracket"), 4, "frictionless", top=2).found),
        "glyph-A-two-fingers.png": lambda: plot_regions(
            synthesize(glyph("A"), 2, "hard", 0.3, top=3).found),
        "glyph-e-two-fingers.png": lambda: plot_regions(
            synthesize(glyph("e"), 2, "hard", 0.5, top=3).found),
        "frame-four-frictionless.png": lambda: plot_regions(
            synthesize(bundled("frame"), 4, "frictionless", top=1).found),
        "triangle-vertex.png": lambda: plot_regions(
            synthesize(bundled("triangle"), 2, "soft", 0.3, top=3,
                       construction="vertices").found),
        "holed-block.png": lambda: plot_object(bundled("holed-block")),
        "pybullet-duck.png": lambda: plot_object(
            load_object(Path(pybullet_data.getDataPath()) / "duck.obj"), up="y"),
        "l-prism-two-soft.png": lambda: plot_spatial_regions(
            synthesize(bundled("l-prism"), 2, "soft", 0.5, top=1).found[0]),
        "cube-three-hard.png": lambda: plot_spatial_regions(
            synthesize(bundled("cube"), 3, "hard", 0.5, top=1).found[0]),
        "duck-three-hard.png": lambda: plot_spatial_regions(synthesize(
            load_object(Path(pybullet_data.getDataPath()) / "duck.obj"), 3, "hard", 0.5,
            top=1).found[0], up="y"),
        "bunny-two-soft.png": lambda: plot_spatial_regions(synthesize(
            load_object(Path(pybullet_data.getDataPath()) / "bunny.obj"), 2, "soft", 0.5,
            top=1).found[0]),
    }
    for name, draw in pictures.items():
        fig = draw()
        fig.savefig(HERE / name, dpi=90, bbox_inches="tight")  # a bare Figure: nothing to close
        print(HERE / name)


if __name__ == "__main__":
    main()
