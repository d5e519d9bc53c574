import json
import os
import subprocess
import sys
from pathlib import Path

import pybullet_data
import pytest

from forceclosure.app.cli import main
from forceclosure.objects import POLYGONS, POLYHEDRA

BAD = Path(__file__).parents[1] / "data" / "bad_objects"


def test_objects_lists_every_bundled_object(capsys):
    assert main(["objects"]) == 0
    out = capsys.readouterr().out
    assert all(name in out for name in [*POLYGONS, *POLYHEDRA])


@pytest.mark.parametrize("name", [*POLYGONS, *POLYHEDRA])
def test_inspect_every_bundled_object_with_a_picture(name, tmp_path, capsys):
    picture = tmp_path / f"{name}.png"
    assert main(["inspect", name, "--plot", str(picture)]) == 0
    assert picture.stat().st_size > 5000
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    out = capsys.readouterr().out
    assert out.startswith(f"{name}: ")


def test_inspect_the_pybullet_duck(tmp_path, capsys):
    duck = os.path.join(pybullet_data.getDataPath(), "duck.obj")
    assert main(["inspect", duck, "--json", "--plot", str(tmp_path / "duck.svg")]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["watertight"] and info["triangles"] == 4212 and info["volume"] > 0
    assert info["warnings"] == ["merged 169 duplicate vertices"]
    assert (tmp_path / "duck.svg").read_text().lstrip().startswith("<?xml")


EXPECTED = {
    "empty.stl": "the file is empty",
    "truncated.stl": "truncated.stl: ",
    "nan_vertices.obj": "vertex 3 is not finite",
    "degenerate_triangle.obj": "triangle 6 is degenerate",
    "garbage.ply": "cannot read the PLY file",
    "unknown_type.xyz": "unknown file type '.xyz'",
    "bowtie.json": "self-intersection at (1, 1)",
    "self_touching.geojson": "self-intersection at (2, 4)",
    "repeated_vertices.csv": "vertex 3 repeats vertex 2",
    "zero_length_edge.svg": "vertex 3 repeats vertex 2",
    "two_vertices.json": "fewer than 3 distinct vertices",
    "hole_outside.json": "hole lies outside shell",
    "wrong.json": "not valid JSON",
    "curve.svg": "<path id=\"loop\">: invalid polygon: self-intersection at (",
    "bad_number.csv": "line 3: expected two numbers",
}


#: Meshes inspect describes (exit 0) but synthesize and dataset refuse without --allow-open.
DESCRIBED = {
    "non_manifold.obj": ("non-manifold edge from (1, 0, 0) to (0, 0, 0)",
                         "non-manifold (not watertight): 1 non-manifold edges"),
    "open_mesh.obj": ("open mesh, 4 boundary edges",
                      "open (not watertight): 4 boundary edges in 1 hole"),
}


def test_the_corpus_is_covered():
    assert {p.name for p in BAD.iterdir()} == set(EXPECTED) | set(DESCRIBED)


@pytest.mark.parametrize("name", sorted(DESCRIBED))
def test_open_and_non_manifold_meshes_are_described_and_refused_by_synthesize(name, capsys):
    refusal, facts = DESCRIBED[name]
    assert main(["inspect", str(BAD / name)]) == 0
    out = capsys.readouterr().out
    assert facts in out and "synthesize and dataset need --allow-open" in out
    assert main(["synthesize", str(BAD / name), "--contact", "soft"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and refusal in lines[0] and "--allow-open" in lines[0], lines


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_bad_objects_one_line_exit_2(name, capsys):
    assert main(["inspect", str(BAD / name)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and captured.out == "", captured
    assert EXPECTED[name] in lines[0], lines[0]


def test_a_bad_object_in_a_real_process_is_one_line_and_exit_2():
    """The same through the installed entry point, as a shell runs it: no traceback."""
    name = "truncated.stl"
    proc = subprocess.run([sys.executable, "-m", "forceclosure.app.cli", "inspect",
                           str(BAD / name)], capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert EXPECTED[name] in lines[0], lines[0]


def test_open_mesh_opt_in(capsys):
    assert main(["inspect", str(BAD / "open_mesh.obj"), "--allow-open"]) == 0
    out = capsys.readouterr().out
    assert "open (not watertight)" in out and "need --allow-open" not in out
    assert main(["inspect", str(BAD / "open_mesh.obj"), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert (info["watertight"], info["boundary_edges"], info["holes"], info["defects"]) == (
        False, 4, 1, ["open"])


def test_bad_plot_path(capsys):
    assert main(["inspect", "cube", "--plot", "/tmp/x.jpeg"]) == 2
    assert "saved as .png or .svg" in capsys.readouterr().err
