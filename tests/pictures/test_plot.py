"""The pictures of objects and regions (forceclosure.pictures.plot): what they draw, where, and what
they leave alone.

PNGs are read back with PIL (not matplotlib) and searched for matplotlib's
documented tab10 colours, written out here by hand; where drawn lines must
lie is checked against the cube's own geometry (|x|, |y|, |z| <= 1); which
faces a camera sees is worked out by hand from the camera angles.
"""

from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import matplotlib.colors
import numpy as np
import pybullet_data
import pytest
from PIL import Image

from forceclosure import load_object
from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.objects import bundled
from forceclosure.pictures.plot import (
    plot_object,
    plot_regions,
    plot_spatial_regions,
    upright_axis,
)
from forceclosure.synthesis import synthesize

#: matplotlib's tab10, the first four (blue, orange, green, red), from its documentation.
TAB10 = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728")


def _pixels(path, hex_colour, tol=40) -> int:
    rgb = np.array(Image.open(path).convert("RGB"), dtype=int)
    target = np.array([int(hex_colour[k:k + 2], 16) for k in (1, 3, 5)])
    return int(np.sum(np.abs(rgb - target).sum(axis=2) < tol))


@pytest.fixture(scope="module")
def cube_three_hard():
    return synthesize(bundled("cube"), 3, "hard", 0.5, top=1).found[0]


@pytest.fixture(scope="module")
def cube_soft_pair():
    return synthesize(bundled("cube"), 2, "soft", 0.5, top=1).found[0]


def test_import_and_pictures_leave_the_backend_and_pyplot_alone(tmp_path):
    script = f"""
import sys, matplotlib
backend = lambda: dict.__getitem__(matplotlib.rcParams, "backend")  # get_backend() loads pyplot
before = backend()
import forceclosure.pictures.plot as fp
from forceclosure.objects import bundled
from forceclosure.synthesis import soft_pair_regions, synthesize
after_import = backend() == before and "matplotlib.pyplot" not in sys.modules
fp.plot_object(bundled("square"), {str(tmp_path / 'a.png')!r})
fp.plot_object(bundled("cube"), {str(tmp_path / 'b.png')!r})
square = synthesize(bundled("square"), 2, "hard", 0.3, top=1).found
fp.plot_regions(square, {str(tmp_path / 'c.png')!r})
fp.plot_spatial_regions(soft_pair_regions(bundled("cube"), 0, 1, 0.5), {str(tmp_path / 'd.svg')!r})
print(after_import, "matplotlib.pyplot" in sys.modules, backend() == before)
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True", "False", "True"]
    assert all((tmp_path / name).stat().st_size > 1000 for name in
               ("a.png", "b.png", "c.png", "d.svg"))


def test_no_figure_left_open(tmp_path, cube_soft_pair):
    import matplotlib.pyplot as plt  # here only to count pyplot's figures

    square = bundled("square")
    regions = synthesize(square, 2, "hard", 0.3, top=2).found
    before = plt.get_fignums()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # pyplot's "More than 20 figures" would fail here
        for k in range(8):
            plot_object(square, tmp_path / f"o{k}.png")
            plot_regions(regions, tmp_path / f"r{k}.png")
            plot_spatial_regions(cube_soft_pair, tmp_path / f"s{k}.png")
    assert plt.get_fignums() == before


def test_ax_draws_into_the_users_axes(cube_soft_pair):
    from matplotlib.figure import Figure

    fig = Figure()
    flat, solid = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2, projection="3d")
    square = bundled("square")
    assert plot_regions(synthesize(square, 2, "hard", 0.3, top=1).found, ax=flat) is fig
    assert len(flat.lines) >= 2 + 4  # two bold segments, four cone rays
    assert plot_object(square, ax=flat, title="mine") is fig
    assert flat.get_title() == "mine"
    assert plot_spatial_regions(cube_soft_pair, ax=solid) is fig
    assert len(solid.collections) >= 1 + 2 * 2  # the object, each region and its cone
    assert len(fig.axes) == 2  # nothing added beside the user's axes
    with pytest.raises(InputError, match="3-D axes"):
        plot_spatial_regions(cube_soft_pair, ax=flat)
    with pytest.raises(InputError, match="2-D axes"):
        plot_regions(synthesize(square, 2, "hard", 0.3, top=1).found, ax=solid)


def test_every_finger_drawn_labelled_and_in_its_colour(tmp_path, cube_three_hard):
    """Two fingers on the top face and one underneath (class 3): all three colours are on
    the picture, the one underneath seen through the object."""
    png = tmp_path / "cube.png"
    fig = plot_spatial_regions(cube_three_hard, png)
    assert [t.get_text() for t in fig.axes[0].texts] == [
        "finger 1", "finger 2", "finger 3 (behind)"]
    for colour in TAB10[:3]:
        assert _pixels(png, colour) > 150, colour
    assert _pixels(png, TAB10[3]) == 0  # no fourth finger


def test_cones_stand_outside_the_object(cube_soft_pair):
    """Every line of a friction cone lies outside the cube (|x|, |y| or |z| >= 1), and
    reaches away from it (as the HTML view draws them)."""
    fig = plot_spatial_regions(cube_soft_pair)
    lines = fig.axes[0].lines
    assert len(lines) == 2 * (1 + 4)  # per finger: the rim and four generators
    for line in lines:
        xyz = np.column_stack(line.get_data_3d())
        assert np.all(np.abs(xyz).max(axis=1) >= 1 - 1e-9)
        assert np.abs(xyz).max() > 1.3


def test_only_faces_in_sight_are_numbered(tmp_path):
    """Seen from elevation 24 deg, azimuth -58 deg, the camera lies along
    (cos 24 cos -58, cos 24 sin -58, sin 24) = (+0.48, -0.77, +0.41): the cube's faces
    towards +x, -y and +z are in sight, the other three not."""
    cube = bundled("cube")
    fig = plot_object(cube, tmp_path / "cube.png")
    numbers = sorted(int(t.get_text()) for t in fig.axes[0].texts)
    seen = sorted(f.index for f in cube.faces if f.normal @ [1, 0, 0] > 0.5
                  or f.normal @ [0, -1, 0] > 0.5 or f.normal @ [0, 0, 1] > 0.5)
    assert numbers == seen and len(seen) == 3
    # The holed block (4 x 4 x 1.5, a 2 x 2 hole through it): of the faces turned towards
    # the camera e = (0.484, -0.775, 0.407) -- top (0), front (2), right (3), and the
    # hole's walls at x = -1 (6) and y = +1 (7) -- wall 6 is hidden: from its centre
    # (-1, 0, 0.75) the line of sight meets the hole's front wall y = -1 at t = 1/0.775,
    # at height 0.75 + 0.407 t = 1.27 < 1.5. From wall 7's centre (0, 1, 0.75) it leaves
    # through the opening (at z = 1.5: t = 1.84, y = -0.43, x = 0.89).
    block = plot_object(bundled("holed-block")).axes[0]
    assert sorted(t.get_text() for t in block.texts) == ["0", "2", "3", "7"]
    assert not plot_spatial_regions(synthesize(cube, 2, "soft", 0.5, top=1).found[0]).axes[
        0].texts[0].get_text().isdigit()


def test_vertex_grasps_are_drawn(tmp_path, capsys):
    """The triangle held by a soft finger on a vertex: its colour on the picture; with
    ``--vertices`` the command draws them after the two-finger grasps (the third colour)."""
    png = tmp_path / "tri.png"
    plot_regions(synthesize(bundled("triangle"), 2, "soft", 0.3, top=1,
                            construction="vertices").found, png)
    assert _pixels(png, TAB10[0]) > 150
    plain, corners = tmp_path / "plain.png", tmp_path / "corners.png"
    assert main(["synthesize", "square", "--mu", "0.3", "--top", "2", "--plot", str(plain)]) == 0
    assert main(["synthesize", "square", "--mu", "0.3", "--top", "2", "--vertices",
                 "--plot", str(corners)]) == 0
    assert _pixels(plain, TAB10[2]) == 0 < 150 < _pixels(corners, TAB10[2])
    # a polygon no two fingers on edges hold: the picture still comes, of the vertex grasps
    only = tmp_path / "only.png"
    assert main(["synthesize", "triangle", "--mu", "0.3", "--vertices", "--plot",
                 str(only)]) == 0
    assert "picture:" in capsys.readouterr().out and _pixels(only, TAB10[0]) > 150


@pytest.mark.parametrize("command", [["synthesize", "cube", "--fingers", "3", "--contact",
                                      "hard", "--samples", "10000000"], ["inspect", "cube"]])
@pytest.mark.parametrize("name, words", [("x.jpg", "saved as .png or .svg"),
                                         ("x.pdf", "saved as .png or .svg"),
                                         ("nowhere/x.png", "does not exist")])
def test_bad_picture_refused_before_any_work(command, name, words, tmp_path, capsys,
                                             monkeypatch):
    import forceclosure.objects.io

    def no_work(*args, **kwargs):
        raise AssertionError("the object was loaded: work started")

    monkeypatch.setattr(forceclosure.objects.io, "load_object", no_work)
    assert main([*command, "--plot", str(tmp_path / name)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err
    assert not (tmp_path / name).exists()


# -- one front door for any region sets; the object upright by its file's format ------------

def test_plot_found_draws_vertex_grasps_wherever_they_are():
    """A vertex grasp first and two-finger grasps after it: the same picture as the other
    order, the vertex grasp's dot on a corner of the square (+-1, +-1), in the colour of its
    place in the list (first: blue), labelled v1, each two-finger grasp's number at both of
    its segments."""
    from forceclosure.pictures.plot import plot_found

    square = bundled("square")
    sets = synthesize(square, 2, "hard", 0.3, top=2).found
    (corner,) = synthesize(square, 2, "soft", 0.3, top=1, construction="vertices").found
    for order, colour in (([corner, *sets], TAB10[0]), ([*sets, corner], TAB10[2])):
        ax = plot_found(order).axes[0]
        dots = [line for line in ax.lines if line.get_marker() == "o"]
        assert len(dots) == 1
        xy = np.column_stack(dots[0].get_data()).astype(float)[0]
        assert np.allclose(np.abs(xy), 1.0)  # a corner of the square
        assert matplotlib.colors.to_hex(dots[0].get_color()) == colour
        assert sorted(t.get_text() for t in ax.texts) == ["1", "1", "2", "2", "v1", "v1"]
    with pytest.raises(InputError, match="same object"):
        plot_found([*sets, *synthesize(bundled("triangle"), 2, "soft", 0.3, top=1,
                                       construction="vertices").found])


def _box_file(tmp_path, suffix: str):
    """A 1 x 3 x 1 box, long along y, centred on the origin: an OBJ written as Blender's
    exporter writes one (``o``, ``v``, ``s off``, 1-based ``f`` quads), or trimesh's STL."""
    import trimesh

    box = trimesh.creation.box((1.0, 3.0, 1.0))
    path = tmp_path / f"tall{suffix}"
    if suffix == ".obj":
        lines = ["# Blender 4.1", "o Tall", *(f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in
                                             box.vertices), "s 0"]
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in box.faces]
        path.write_text("\n".join(lines) + "\n")
    else:
        box.export(path)
    return path, box.vertices


@pytest.mark.parametrize("suffix, up", [(".obj", "y"), (".stl", "z")])
def test_synthesize_plot_stands_the_object_up_by_its_format(tmp_path, monkeypatch, suffix, up):
    """``--plot`` of a box 3 long along y: from an OBJ (y-up by convention) the picture shows
    it standing, 3 tall on the screen against about 1.4 wide; from an STL (z-up) lying.
    Measured on the screen: the box's corners projected by the picture's own camera, and
    the file format's up axis drawn pointing up the screen (to perspective's slant)."""
    from mpl_toolkits.mplot3d import proj3d

    import forceclosure.pictures.plot

    drawn = []
    real = forceclosure.pictures.plot.plot_found

    def keep(*args, **kwargs):
        drawn.append(real(*args, **kwargs))
        return drawn[-1]

    monkeypatch.setattr(forceclosure.pictures.plot, "plot_found", keep)
    path, corners = _box_file(tmp_path, suffix)
    assert forceclosure.pictures.plot.upright_axis(path) == up
    assert main(["synthesize", str(path), "--fingers", "2", "--contact", "soft", "--mu", "0.5",
                 "--top", "1", "--plot", str(tmp_path / "x.png")]) == 0
    ax = drawn[0].axes[0]
    sx, sy, _ = proj3d.proj_transform(*corners.T, ax.get_proj())
    tall = (sy.max() - sy.min()) / (sx.max() - sx.min())
    assert tall > 1.5 if up == "y" else tall < 1.0
    step = np.eye(3)["xyz".index(up)]
    xs, ys, _ = proj3d.proj_transform(*np.array([np.zeros(3), step]).T, ax.get_proj())
    assert abs(xs[1] - xs[0]) < 0.05 * (ys[1] - ys[0])  # the up axis points up the screen


def test_grasps_sharing_a_vertex_all_show():
    """On the triangle at mu 0.3 three of the five vertex grasps have a finger on the vertex
    (-1, 0) (two pair it with the other vertices): their dots there are rings, each drawn
    smaller than the one under it, so that none hides another."""
    corners = synthesize(bundled("triangle"), 2, "soft", 0.3, top=5,
                         construction="vertices").found
    ax = plot_regions(corners).axes[0]
    at = [line for line in ax.lines if line.get_marker() == "o"
          and np.allclose(np.column_stack(line.get_data()).astype(float)[0], [-1, 0])]
    sizes = [line.get_markersize() for line in sorted(at, key=lambda line: line.zorder)]
    assert len(sizes) == 3 and sizes == sorted(sizes, reverse=True) and len(set(sizes)) == 3


# -- upright by the file's convention and the object's shape ----------------------------------

PYBULLET = Path(pybullet_data.getDataPath())


@pytest.mark.parametrize("name, up", [
    ("duck_vhacd.urdf", "y"),     # a URDF placing y-up OBJs unturned: the duck stands on y
    ("teddy_vhacd.urdf", "y"),    # likewise the sitting bear
    ("objects/mug.urdf", "z"),    # OBJs too, but the mug was written z-up: its base is z = 0
    ("objects/mug.obj", "z"),
    ("duck.obj", "y"),
])
def test_pybullet_objects_stand_upright(name, up):
    """pybullet_data's duck, teddy and mug stand upright (looked at: docs/gripper.md). The
    mug's case checked from its data here: the vertices on its lowest z plane span a disc
    as wide as the mug (its base), while on its lowest y it touches along a line (its side),
    so it stands on z and the OBJ convention's y is overruled."""
    obj = load_object(str(PYBULLET / name), allow_open=True)
    assert upright_axis(PYBULLET / name, obj) == up
    if "mug" in name:
        V = obj.vertices
        base = V[V[:, 2] <= V[:, 2].min() + 1e-6]
        side = V[V[:, 1] <= V[:, 1].min() + 1e-6]
        assert np.ptp(base[:, 0]) > 0.07 and np.ptp(base[:, 1]) > 0.07  # a disc, 0.082 wide
        assert np.ptp(side[:, 0]) < 1e-3  # a line along z


def test_standing_is_the_tipping_angle_of_a_box():
    """A box of half-sides (a, b, c) centred anywhere stands on each axis by the angle it
    tips over at: atan(the smaller half-side across / the half-side along the axis)."""
    import trimesh

    from forceclosure.pictures.plot import standing

    rng = np.random.default_rng(5)
    for _ in range(20):
        half = rng.uniform(0.1, 3.0, size=3)
        box = trimesh.creation.box(2 * half)
        box.apply_translation(rng.normal(size=3) * 10)
        found = standing(box.vertices)
        for k, axis in enumerate("xyz"):
            across = np.delete(half, k).min()
            assert found[axis] == pytest.approx(np.degrees(np.arctan(across / half[k])),
                                                abs=1e-6)


def test_a_urdf_is_upright_as_its_meshes_unless_it_turns_them(tmp_path):
    """A URDF placing a y-up OBJ (a box 3 tall along y) unturned is drawn y-up; turned by a
    quarter turn about x (rpy) it is z-up, as REP 103 says; a box of the URDF's own is z-up."""
    import trimesh

    trimesh.creation.box((1.0, 3.0, 1.0)).export(tmp_path / "tall.obj")
    for rpy, up in (("0 0 0", "y"), ("1.5707963 0 0", "z")):
        urdf = tmp_path / f"tall{up}.urdf"
        urdf.write_text(f'<robot name="r"><link name="a"><collision><origin rpy="{rpy}"/>'
                        '<geometry><mesh filename="tall.obj"/></geometry></collision></link>'
                        "</robot>")
        assert upright_axis(urdf) == up
    box = tmp_path / "box.urdf"
    box.write_text('<robot name="r"><link name="a"><collision><geometry><box size="1 3 1"/>'
                   "</geometry></collision></link></robot>")
    assert upright_axis(box) == "z"
