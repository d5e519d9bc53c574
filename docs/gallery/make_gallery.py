"""Regenerate the pictures of docs/gallery.md.

    uv run python docs/gallery/make_gallery.py
"""

from pathlib import Path

import pybullet_data

from forceclosure.objects import bundled, glyph
from forceclosure.objects.io import load_object
from forceclosure.pictures.plot import plot_object, plot_regions, plot_spatial_regions
from forceclosure.synthesis import (
    best_frictionless_regions,
    best_regions,
    best_soft_pair_regions,
    best_three_finger_regions,
    best_three_hard_regions,
    vertex_grasps,
)
from forceclosure.synthesis.best import synthesize

HERE = Path(__file__).parent


def main() -> None:
    pictures = {
        "wrench-head-two-fingers.png": lambda: plot_regions(
            best_regions(bundled("wrench-head"), 0.3, top=3)),
        "wrench-head-nguyen.png": lambda: plot_regions(
            best_regions(bundled("wrench-head"), 0.3, top=3, construction="nguyen")),
        "triangle-three-fingers.png": lambda: plot_regions(
            best_three_finger_regions(bundled("triangle"), 0.3, top=1)),
        "bracket-four-frictionless.png": lambda: plot_regions(
            best_frictionless_regions(bundled("bracket"), top=2)),
        "glyph-A-two-fingers.png": lambda: plot_regions(best_regions(glyph("A"), 0.3, top=3)),
        "glyph-e-two-fingers.png": lambda: plot_regions(best_regions(glyph("e"), 0.5, top=3)),
        "frame-four-frictionless.png": lambda: plot_regions(
            best_frictionless_regions(bundled("frame"), top=1)),
        "triangle-vertex.png": lambda: plot_regions(
            vertex_grasps(bundled("triangle"), 0.3, top=3)),
        "holed-block.png": lambda: plot_object(bundled("holed-block")),
        "pybullet-duck.png": lambda: plot_object(
            load_object(Path(pybullet_data.getDataPath()) / "duck.obj"), up="y"),
        "l-prism-two-soft.png": lambda: plot_spatial_regions(
            best_soft_pair_regions(bundled("l-prism"), 0.5, top=1)[0]),
        "cube-three-hard.png": lambda: plot_spatial_regions(
            best_three_hard_regions(bundled("cube"), 0.5, top=1)[0]),
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
