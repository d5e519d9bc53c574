"""The picture of labelled jaw poses: what it draws, what it refuses, what it leaves alone.

The PNG is read back with PIL (not matplotlib) and its pixels searched for
the label colours: green appears when a drawn grasp closes and is clear,
orange when one closes but collides, neither when nothing is drawn.
"""

import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from forceclosure.app.cli import main
from forceclosure.pictures.grasp_plot import COLOURS, best_grasps


def _has_colour(path, hex_colour, tol=40):
    rgb = np.array(Image.open(path).convert("RGB"), dtype=int)
    target = np.array([int(hex_colour[k:k + 2], 16) for k in (1, 3, 5)])
    return int(np.sum(np.abs(rgb - target).sum(axis=2) < tol))


def test_cli_plot_draws_the_labels_colours(tmp_path, capsys):
    png, labels = tmp_path / "g.png", tmp_path / "l.npz"
    assert main(["grasps", "cube", "--width", "2.2", "--count", "60", "--seed", "3",
                 "--clearance", "0.1", "--no-least-friction", "--out", str(labels),
                 "--plot", str(png), "--plot-top", "5", "--approaches", "1", "--depths", "1",
                 "--tilt", "1"]) == 0
    assert "picture of the 5 best" in capsys.readouterr().out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with np.load(labels) as saved:
        clear = int(np.sum((saved["code"] == 2) & ~saved["collides"]))
    assert 0 < clear < 5  # the 5 best: every clear closed grasp, then colliding ones
    assert _has_colour(png, COLOURS["closure"]) > 50
    assert _has_colour(png, COLOURS["closure, collides"]) > 50
    assert _has_colour(png, COLOURS["none"]) == 0
    # nothing drawn: no label colour at all
    empty = tmp_path / "empty.png"
    assert main(["grasps", "cube", "--width", "2.2", "--count", "5", "--no-least-friction",
                 "--plot", str(empty), "--plot-top", "0"]) == 0
    assert all(_has_colour(empty, c) == 0 for c in COLOURS.values())


def _best_order(code, hit, eps, top):
    """The best poses, computed here: clear closed by decreasing epsilon, colliding closed,
    marginal, none; ties by index."""
    hit = np.zeros(len(code), bool) if hit is None else hit
    category = np.where((code == 2) & ~hit, 0, np.where(code == 2, 1,
                                                        np.where(code == 1, 2, 3)))
    return category, sorted(range(len(code)), key=lambda i: (category[i], -eps[i], i))[:top]


def _panel_dots(ax):
    """The contact dots drawn in a panel (the one scatter of two points)."""
    from mpl_toolkits.mplot3d.art3d import Path3DCollection

    (dots,) = [c for c in ax.collections if isinstance(c, Path3DCollection)]
    return np.column_stack([np.asarray(v, dtype=float) for v in dots._offsets3d])


def test_one_panel_per_pose_and_the_legend_counts_the_labels():
    """Small multiples: one panel per pose, in rank order, its contact dots on that pose's
    contacts and its caption naming its rank, verdict and hand; the legend's counts are
    the poses of each label drawn and in all, counted here from the label arrays."""
    from forceclosure import ParallelJaw
    from forceclosure.gripper.labels import grasp_labels
    from forceclosure.pictures.grasp_plot import grasps_picture

    labels = grasp_labels("cube", ParallelJaw(2.2), 0.5, 60, seed=3, least_friction=False,
                          clearance=0.1, approaches=1, depths=1, tilt=1.0)
    code, hit = labels.code, labels.collides
    category, order = _best_order(code, hit, labels.epsilon, 4)
    fig = grasps_picture("cube", labels, top=4)
    assert len(fig.axes) == 4
    for rank, (ax, i) in enumerate(zip(fig.axes, order, strict=True), start=1):
        first = ax.get_title().splitlines()[0]
        assert first == f"{rank}. closure, {'collides' if hit[i] else 'clear'}"
        assert np.allclose(_panel_dots(ax), labels.points[i])
    words = ("closure and clear", "closure, hand collides", "marginal", "none")
    drawn = np.bincount(category[order], minlength=4)
    total = np.bincount(category, minlength=4)
    expected = [f"{words[k]}: {drawn[k]} drawn of {total[k]}" for k in range(4) if drawn[k]]
    assert [t.get_text() for t in fig.legends[0].get_texts()] == expected
    assert expected[0].startswith("closure and clear: ")  # the case is not empty
    # without the collision check, "closure" is said as unchecked, not "clear"
    unchecked = grasp_labels("cube", ParallelJaw(2.2), 0.5, 6, seed=3, least_friction=False,
                             collision=False)
    fig = grasps_picture("cube", unchecked, top=2)
    n = int(np.sum(unchecked.code == 2))
    assert fig.legends[0].get_texts()[0].get_text() == \
        f"closure (hand not checked): {min(n, 2)} drawn of {n}"
    assert "hand not checked" in fig.axes[0].get_title()
    # nothing to draw: the object alone, no legend
    fig = grasps_picture("cube", labels, top=0)
    assert len(fig.axes) == 1 and not fig.legends


def test_plot_refused_before_any_work(tmp_path, capsys):
    for name, words in (("g.jpg", "saved as .png or .svg"), ("g.png", "--plot-top")):
        extra = ["--plot-top", "-1"] if name == "g.png" else []
        assert main(["grasps", "cube", "--width", "3", "--count", "100000",
                     "--plot", str(tmp_path / name), *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and words in err
        assert not (tmp_path / name).exists()


def test_best_grasps_order():
    class L:
        code = np.array([0, 2, 1, 2, 2, 2])
        collides = np.array([False, True, False, False, False, True])
        epsilon = np.array([0.0, 0.9, 0.0, 0.2, 0.4, 0.1])
    # clear closed by decreasing epsilon (4, 3), colliding closed (1, 5), marginal, none
    assert best_grasps(L, 10).tolist() == [4, 3, 1, 5, 2, 0]
    L.collides = None  # not checked: closure alone
    assert best_grasps(L, 3).tolist() == [1, 4, 3]


def test_no_pyplot_and_no_backend_switch(tmp_path):
    script = f"""
import sys, types, numpy as np, matplotlib
backend = lambda: dict.__getitem__(matplotlib.rcParams, "backend")  # get_backend() loads pyplot
before = backend()
from forceclosure.pictures.grasp_plot import plot_grasps
labels = types.SimpleNamespace(
    code=np.array([2]), collides=np.array([False]), epsilon=np.array([0.1]),
    center=np.zeros((1, 3)), closing_axis=np.array([[1.0, 0, 0]]),
    approach_axis=np.array([[0, 0, -1.0]]), width=np.array([2.0]),
    points=np.array([[[-1.0, 0, 0], [1.0, 0, 0]]]), meta={{"width_max": 3.0}})
plot_grasps("cube", labels, {str(tmp_path / 'one.png')!r}, top=1)
print("matplotlib.pyplot" in sys.modules, backend() == before)
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "True"]
    assert (tmp_path / "one.png").stat().st_size > 0


@pytest.mark.parametrize("suffix", [".svg"])
def test_svg_too(tmp_path, suffix):
    assert main(["grasps", "cube", "--width", "3", "--count", "5", "--no-least-friction",
                 "--no-collision", "--plot", str(tmp_path / f"g{suffix}")]) == 0
    assert (tmp_path / f"g{suffix}").read_text().lstrip().startswith("<?xml")


def test_grasp_pictures_hold_the_up_axis_upright():
    """A y-up mesh file (OBJ) keeps y upright in the page's camera; a bad axis is refused."""
    from forceclosure import InputError, ParallelJaw
    from forceclosure.gripper.labels import grasp_labels
    from forceclosure.pictures.plot import upright_axis
    from forceclosure.pictures.view import grasps_figure

    labels = grasp_labels("cube", ParallelJaw(3.0), 0.3, 6, least_friction=False)
    up = grasps_figure("cube", labels, 2, up=upright_axis("duck.obj")).layout.scene.camera.up
    assert (up.x, up.y, up.z) == (0.0, 1.0, 0.0)
    with pytest.raises(InputError, match="up must be"):
        grasps_figure("cube", labels, 2, up="w")


def test_the_hand_stands_where_the_pose_puts_it():
    """The drawn hand of a pose, in the jaw frame (x the approach axis, y the closing
    axis): its fingers' inner faces at +-(width/2 + clearance), their tips at the pose's
    own depth past the jaw centre where the labels have one (else the gripper's), and the
    stem ending tip_offset behind the tips where the labels state one."""
    from types import SimpleNamespace

    from forceclosure import ParallelJaw
    from forceclosure.pictures.grasp_scene import grasp_scene

    hand = ParallelJaw(3.0)  # depth 0.6, fingers 1.5 long, 0.3 thick
    c, x, a = np.array([0.1, 0.2, 0.3]), np.array([1.0, 0, 0]), np.array([0, 0, -1.0])
    labels = SimpleNamespace(
        code=np.array([2, 2]), collides=np.array([False, False]), epsilon=np.array([0.2, 0.1]),
        least_friction=np.array([0.1, 0.2]), center=np.array([c, c]),
        closing_axis=np.array([x, x]), approach_axis=np.array([a, a]),
        width=np.array([2.0, 2.0]), points=np.array([[c - x, c + x]] * 2),
        normals=np.array([[-x, x]] * 2), depth=np.array([0.6, 0.2]),
        meta={"mu": 0.5, "width_max": 3.0, "collision": {"clearance": 0.05},
              "tip_offset": 2.5})
    scene = grasp_scene("cube", labels, np.array([0, 1]), hand)
    for pose, depth in zip(scene.poses, (0.6, 0.2), strict=True):
        along = (pose.boxes - c) @ a  # the approach coordinate of every corner
        across = (pose.boxes - c) @ x
        fingers = pose.boxes[:2]
        assert np.isclose(along[:2].max(), depth) and np.isclose(along[:2].min(), depth - 1.5)
        assert np.isclose(np.abs(across[:2]).min(), 1.0 + 0.05)  # the inner faces
        assert np.isclose(np.abs(across[:2]).max(), 1.0 + 0.05 + 0.3)
        assert np.allclose(fingers.mean(axis=1)[:, 1:], c[1:] + [[0, -depth + 0.75]] * 2)
        assert np.isclose((pose.stem[1] - c) @ a, depth - 2.5)  # the hand's base frame
        # the cones point into the cube: their rims lie between the contacts
        assert np.all(np.abs((pose.cones[:, 1:] - c) @ x) < 1.0)
