"""Bad files found by trying them as an attacker would: one line each, never an internal error.

Each file is written here by hand (its fault is the point of it); the command runs in this
process and must end with exit status 2 and one line naming the file and its fault.
"""

import io
import zipfile

import numpy as np
import pytest

from forceclosure.app.cli import main
from forceclosure.contacts import MAX_CONTACTS
from forceclosure.errors import InputError
from forceclosure.io.grasp_arrays import open_npz
from forceclosure.objects.io import load_object
from forceclosure.objects.svg import MAX_DEPTH


def one_line(argv, capsys) -> str:
    status = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1, (status, err)
    assert "internal error" not in err[0]
    return err[0]


@pytest.mark.parametrize("features", ["5", '"abc"', '{"a": 1}', "true"])
def test_feature_collection_whose_features_are_not_a_list(tmp_path, capsys, features):
    path = tmp_path / "fc.geojson"
    path.write_text(f'{{"type": "FeatureCollection", "features": {features}}}')
    for command in ("inspect", "synthesize"):
        line = one_line([command, str(path)], capsys)
        assert "fc: the FeatureCollection's 'features' must be a list" in line


def test_csv_field_over_the_csv_limit(tmp_path, capsys):
    """csv refuses a field over 131,072 characters with its own error; it is the file's
    fault (line 3), said in one line."""
    path = tmp_path / "big.csv"
    path.write_text("x,y\n0,0\n1," + "1" * 140_000 + "\n0,1\n")
    line = one_line(["inspect", str(path)], capsys)
    assert "big: line 3: not CSV coordinates: field larger than field limit" in line
    # a field just under the limit is only a bad number, as any other
    path.write_text("x,y\n0,0\n1," + "1" * 1000 + "x\n0,1\n")
    assert "line 3: expected two numbers" in one_line(["inspect", str(path)], capsys)


def test_deeply_nested_svg_groups(tmp_path, capsys):
    """100,000 nested <g>: refused by its depth (counted without recursion), not by Python's
    recursion limit; a drawing nested MAX_DEPTH deep reads (its triangle: area 1/2)."""
    def svg(depth: int) -> str:
        return ('<svg xmlns="http://www.w3.org/2000/svg">' + "<g>" * depth
                + '<path d="M0 0 L1 0 L0 1 Z"/>' + "</g>" * depth + "</svg>")

    path = tmp_path / "deep.svg"
    path.write_text(svg(100_000))
    line = one_line(["inspect", str(path)], capsys)
    assert "deep: elements nested 100,002 deep; at most 200 levels are read" in line
    assert "recursion" not in line
    path.write_text(svg(MAX_DEPTH - 2))  # the <svg>, the groups and the <path>
    assert load_object(path).area == pytest.approx(0.5)


def lying_npz(path, shape) -> None:
    """An .npz whose points and normals headers claim ``shape`` over 48 bytes of data."""
    with zipfile.ZipFile(path, "w") as archive:
        for name in ("points", "normals"):
            header = io.BytesIO()
            np.lib.format.write_array_header_1_0(header, {
                "descr": "<f8", "fortran_order": False, "shape": shape})
            archive.writestr(name + ".npy", header.getvalue() + bytes(48))


@pytest.mark.parametrize("shape", [(1, 10**10, 3), (0, 10**10, 3), (2, MAX_CONTACTS + 1, 2)])
def test_npz_header_with_too_many_contacts(tmp_path, capsys, shape):
    """A header claiming 1e10 contacts a grasp made a list of 1e10 model names (MemoryError);
    now k above MAX_CONTACTS is refused before anything is made of it."""
    path = tmp_path / "g.npz"
    lying_npz(path, shape)
    with pytest.raises(InputError, match=rf"{shape[1]:,} contacts a grasp; at most "):
        open_npz(str(path))
    line = one_line(["analyze", str(path)], capsys)
    assert f"{shape[1]:,} contacts a grasp" in line


def test_npz_at_the_contact_cap_is_read(tmp_path):
    """MAX_CONTACTS contacts a grasp: the header is accepted (the arrays are real)."""
    path = tmp_path / "g.npz"
    points = np.zeros((1, MAX_CONTACTS, 2))
    np.savez(path, points=points, normals=np.ones_like(points), mu=0.5)
    info = open_npz(str(path))
    assert (info.count, info.contacts, info.dim) == (1, MAX_CONTACTS, 2)


def test_tiny_length_scale_leaks_no_warning(tmp_path, capsys):
    """length_scale 1e-320 overflowed numpy's divide (a RuntimeWarning line on standard
    error, an internal error under -W error): now each such grasp is one refusal line, and
    the closed pinch at 1e-100 (Corollary 3: the line between the soft fingers lies inside
    both cones) is still analysed."""
    import json
    import warnings

    pinch = [{"point": [-1, 0.3, 0.2], "normal": [-1, 0, 0], "model": "soft", "mu": 0.5},
             {"point": [1, 0.3, 0.2], "normal": [1, 0, 0], "model": "soft", "mu": 0.5}]
    planar = [{"point": [0, 0], "normal": [0, -1], "model": "hard", "mu": 0.5},
              {"point": [0, 1], "normal": [0, 1], "model": "hard", "mu": 0.5}]
    path = tmp_path / "g.json"
    path.write_text(json.dumps({"grasps": [
        {"length_scale": 1e-320, "contacts": pinch},
        {"length_scale": 1e-100, "contacts": pinch},
        {"length_scale": 1e-320, "contacts": planar}]}))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        status = main(["analyze", str(path), "--json"])
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert status == 2 and len(err) == 2, err
    assert all("the torques overflow" in line for line in err), err
    results = json.loads(captured.out)["results"]
    assert results[1]["verdict"] == "closure"


def test_a_closed_grasp_never_reports_epsilon_0(tmp_path, capsys):
    """A closed grasp's epsilon is positive (the origin is inside the hull, Theorem 1); at
    length scales where doubles do not resolve the hull it came out 0: now it is null with
    the reason said (and so is a margin not resolved there), and at length 1 it is the
    positive number."""
    import json

    pinch = [{"point": [-1, 0, 0], "normal": [-1, 0, 0], "model": "soft", "mu": 0.5},
             {"point": [1, 0, 0], "normal": [1, 0, 0], "model": "soft", "mu": 0.5}]
    path = tmp_path / "g.json"
    path.write_text(json.dumps({"grasps": [{"length_scale": s, "contacts": pinch}
                                           for s in (1.0, 1e-30, 1e-100)]}))
    assert main(["analyze", str(path), "--json"]) == 0
    results = json.loads(capsys.readouterr().out)["results"]
    assert [r["verdict"] for r in results] == ["closure"] * 3
    assert results[0]["epsilon"] > 0
    for r in results[1:]:
        assert r["epsilon"] is None or r["epsilon"] > 0
        if r["epsilon"] is None:
            assert r["null_reasons"]["epsilon"].startswith("not resolved")
        if r["margin"] is None:  # every null says why
            assert r["null_reasons"]["margin"].startswith("not resolved")
    assert main(["analyze", str(path)]) == 0
    assert "epsilon 0 " not in capsys.readouterr().out
