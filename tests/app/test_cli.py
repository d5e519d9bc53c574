import json
import subprocess
import sys
from importlib import resources
from pathlib import Path

import jsonschema
import numpy as np
import pytest

from forceclosure.app.cli import main
from forceclosure.schemas import load_schema

DATA = Path(__file__).parents[1] / "data"
SCHEMA = load_schema("grasp-file")
EXAMPLES = resources.files("forceclosure") / "examples"
RESULT_KEYS = {"verdict", "force_closure", "rank", "margin", "force_direction_closure",
               "torque_closure", "unresisted_twist", "epsilon", "least_friction"}


@pytest.mark.parametrize("name", ["planar.json", "spatial.json"])
def test_bundled_examples_follow_the_schema(name):
    jsonschema.validate(json.loads((EXAMPLES / name).read_text()), SCHEMA)


def test_demo_runs(capsys):
    assert main(["demo"]) == 0
    out = capsys.readouterr().out
    assert "rotation in either direction about the axis through (0, 0.3, 0.2)" in out
    assert out.count("closure: rank") >= 6


def test_analyze_json_contract(tmp_path, capsys):
    path = tmp_path / "g.json"
    path.write_text((EXAMPLES / "spatial.json").read_text())
    assert main(["analyze", str(path), "--json"]) == 0
    results = json.loads(capsys.readouterr().out)["results"]
    assert len(results) == 6
    assert all(set(r) >= RESULT_KEYS for r in results)
    antipodal = results[0]
    assert antipodal["verdict"] == "none" and antipodal["rank"] == 5
    assert antipodal["force_closure"] is False and antipodal["torque_closure"] is False
    assert antipodal["epsilon"] is None and antipodal["least_friction"] is None
    assert len(antipodal["unresisted_twist"]) == 6
    soft = results[1]
    assert soft["verdict"] == "closure" and soft["unresisted_twist"] is None
    assert soft["epsilon"] > 0


def test_single_grasp_file_and_stdin(monkeypatch, capsys):
    text = json.dumps({"contacts": [{"point": [-1, 0], "normal": [-1, 0], "mu": 0.3},
                                    {"point": [1, 0], "normal": [1, 0], "mu": 0.3}]})
    jsonschema.validate(json.loads(text), SCHEMA)
    monkeypatch.setattr(sys, "stdin", __import__("io").StringIO(text))
    assert main(["analyze", "-"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("grasp 1: closure") and "least friction 0" in out


def test_one_bad_grasp_does_not_stop_the_others(tmp_path, capsys):
    good = {"contacts": [{"point": [-1, 0], "normal": [-1, 0], "mu": 0.3},
                         {"point": [1, 0], "normal": [1, 0], "mu": 0.3}]}
    bad = {"name": "broken", "contacts": [{"point": [0, 1], "normal": [0, 0]}]}
    path = tmp_path / "g.json"
    path.write_text(json.dumps({"grasps": [good, bad, good]}))
    assert main(["analyze", str(path), "--json"]) == 2
    captured = capsys.readouterr()
    results = json.loads(captured.out)["results"]
    assert [r.get("verdict") for r in results] == ["closure", None, "closure"]
    assert results[1]["error"].startswith('grasp 2 ("broken"): contact 1: field \'normal\'')
    assert captured.err.strip().count("\n") == 0 and "zero vector" in captured.err


EXPECTED = {
    "empty.json": "not valid JSON",
    "truncated.json": "not valid JSON",
    "not_an_object.json": "top level must be an object",
    "no_grasps.json": "'grasps' must be a non-empty list",
    "zero_normal.json": "grasp 1: contact 1: field 'normal' is a zero vector",
    "nan_point.json": "grasp 1: contact 1: field 'point' must be finite",
    "negative_mu.json": "grasp 1: contact 1: field 'mu' must be >= 0",
    "mixed_dimensions.json": "contact 2: 3-D, but contact 1 is 2-D",
    "missing_point.json": "grasp 1: contact 1: give exactly one of 'point' and 'points'",
    "unknown_model.json": "grasp 1: contact 1: field 'model' must be one of",
    "mu_not_a_number.json": "grasp 1: contact 1: field 'mu' must be a number",
    "cone_too_few_edges.json": "'edges' must be an integer >= 3",
    "infinite_mu.json": "grasp 1: contact 1: field 'mu' must be finite",
    "binary.json": "not a text file",
}


def test_every_bad_file_is_covered():
    assert {p.name for p in (DATA / "bad").iterdir()} == set(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_bad_input_is_one_line_and_exit_2(name, capsys):
    assert main(["analyze", str(DATA / "bad" / name)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and captured.out == "", captured
    assert EXPECTED[name] in lines[0], lines[0]


def test_bad_input_in_a_real_process_is_one_line_and_exit_2():
    """The same through the installed entry point, as a shell runs it: no traceback."""
    name = "nan_point.json"
    proc = subprocess.run([sys.executable, "-m", "forceclosure.app.cli", "analyze",
                           str(DATA / "bad" / name)], capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert EXPECTED[name] in lines[0], lines[0]


def test_missing_file_and_usage_errors(capsys):
    assert main(["analyze", "/no/such/file.json"]) == 2
    assert "no such file" in capsys.readouterr().err
    for argv in (["analyze"], ["synthesize", "square", "--mu", "abc"], ["bogus"]):
        with pytest.raises(SystemExit) as e:
            main(argv)
        assert e.value.code == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("forceclosure: error: "), err
        assert "--help')" in err


@pytest.mark.parametrize("script", sorted((Path(__file__).parents[2] / "examples").glob("*.py")))
def test_examples_run(script):
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "force-closure" in proc.stdout or "closure" in proc.stdout


def _pinches(n, rng):
    """Planar two-finger pinches with a closed form: closure iff |offset| / 2 < mu."""
    y = rng.uniform(-1, 1, n)
    mu = rng.uniform(0.05, 0.6, n)
    mu = np.where(np.abs(np.abs(y) / 2 - mu) < 1e-3, mu + 0.01, mu)  # clear of the boundary
    P = np.stack([np.c_[-np.ones(n), np.zeros(n)], np.c_[np.ones(n), y]], 1)
    N = np.array([[-1.0, 0.0], [1.0, 0.0]])[None].repeat(n, 0)
    return P, N, np.repeat(mu[:, None], 2, 1), np.abs(y) / 2 < mu


@pytest.mark.parametrize("chunk", ["7", "65536"])
def test_analyze_npz_summary_and_results(tmp_path, capsys, chunk):
    P, N, mu, closed = _pinches(50, np.random.default_rng(4))
    path = tmp_path / "pinches.npz"
    np.savez_compressed(path, points=P, normals=N, mu=mu, model="hard")
    out = tmp_path / "results.npz"
    assert main(["analyze", str(path), "--out", str(out), "--chunk", chunk]) == 0
    text = capsys.readouterr().out
    assert f"closure {closed.sum()}, marginal 0, none {50 - closed.sum()}, bad input 0" in text
    results = np.load(out)
    assert list(results["names"]) == ["none", "marginal", "closure"]
    np.testing.assert_array_equal(results["verdict"], np.where(closed, 2, 0))
    np.testing.assert_array_equal(results["rank"], 3)  # planar pinches span the plane
    assert np.all((results["margin"] > 0) == closed)


def test_analyze_npz_epsilon(tmp_path, capsys):
    """Head-on pinches have epsilon mu / sqrt(mu^2 + 2); open grasps 0, bad rows NaN."""
    rng = np.random.default_rng(6)
    n = 40
    mu = rng.uniform(0.1, 1.0, n)
    y = np.where(np.arange(n) % 4 == 0, 3.0, 0.0)  # every fourth pinch far off its line
    P = np.stack([np.c_[-np.ones(n), np.zeros(n)], np.c_[np.ones(n), y]], 1)
    N = np.array([[-1.0, 0.0], [1.0, 0.0]])[None].repeat(n, 0)
    N[5, 1] = 0.0
    path = tmp_path / "pinches.npz"
    np.savez(path, points=P, normals=N, mu=np.repeat(mu[:, None], 2, 1))
    out = tmp_path / "r.npz"
    assert main(["analyze", str(path), "--out", str(out), "--epsilon", "--chunk", "16"]) == 2
    assert "epsilon (L1, 8-edge pyramids) of the closed grasps: median" in capsys.readouterr().out
    eps = np.load(out)["epsilon"]
    head_on = (y == 0) & (np.arange(n) != 5)
    np.testing.assert_allclose(eps[head_on], mu[head_on] / np.sqrt(mu[head_on] ** 2 + 2),
                               rtol=1e-9)
    np.testing.assert_array_equal(eps[y != 0], 0.0)
    assert np.isnan(eps[5])
    json_file = tmp_path / "g.json"
    json_file.write_text("{}")
    assert main(["analyze", str(json_file), "--epsilon"]) == 2
    assert "--epsilon is for .npz grasp files" in capsys.readouterr().err


def test_analyze_npz_bad_rows_are_one_line_each_and_the_rest_is_kept(tmp_path, capsys):
    P, N, mu, closed = _pinches(30, np.random.default_rng(5))
    P[3, 1, 0] = np.nan
    N[17, 0] = 0.0
    mu[21, 1] = -0.5
    path = tmp_path / "bad.npz"
    np.savez(path, points=P, normals=N, mu=mu)
    out = tmp_path / "r.npz"
    assert main(["analyze", str(path), "--out", str(out), "--json"]) == 2
    captured = capsys.readouterr()
    errors = captured.err.strip().splitlines()
    assert [line.split(":")[2].strip() for line in errors] == ["grasp 4, contact 2",
                                                               "grasp 18, contact 1",
                                                               "grasp 22, contact 2"]
    assert all("Traceback" not in line for line in errors)
    summary = json.loads(captured.out)
    assert summary["errors"] == 3 and summary["grasps"] == 30
    assert summary["closure"] + summary["none"] + summary["marginal"] == 27
    verdict = np.load(out)["verdict"]
    good = np.ones(30, bool)
    good[[3, 17, 21]] = False
    np.testing.assert_array_equal(verdict[~good], -1)
    np.testing.assert_array_equal(verdict[good], np.where(closed, 2, 0)[good])


@pytest.mark.parametrize("arrays, message", [
    ({"normals": np.ones((2, 2, 2))}, "'points'"),
    ({"points": np.ones((2, 2, 2)), "normals": np.ones((2, 3, 2))}, "normals"),
    ({"points": np.ones((2, 2, 2)), "normals": np.ones((2, 2, 2)), "model": "sticky"}, "sticky"),
])
def test_analyze_npz_bad_files_exit_2_in_one_line(tmp_path, arrays, message):
    path = tmp_path / "g.npz"
    np.savez(path, **arrays)
    run = subprocess.run([sys.executable, "-m", "forceclosure", "analyze", str(path)],
                         capture_output=True, text=True)
    assert run.returncode == 2
    assert run.stderr.count("\n") == 1 and message in run.stderr, run.stderr
    assert "Traceback" not in run.stderr


def test_analyze_npz_truncated_array_keeps_the_rows_before_it(tmp_path, capsys):
    import io
    import zipfile

    P, N, mu, closed = _pinches(100, np.random.default_rng(6))
    path = tmp_path / "cut.npz"
    np.savez(path, normals=N, mu=mu)
    whole = io.BytesIO()
    np.lib.format.write_array(whole, P)
    cut = whole.getvalue()[: len(whole.getvalue()) - 40 * P[0].nbytes]  # 60 rows of 100
    with zipfile.ZipFile(path, "a") as archive:
        archive.writestr("points.npy", cut)
    out = tmp_path / "r.npz"
    assert main(["analyze", str(path), "--out", str(out), "--chunk", "16"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'points' is truncated" in err[0] and "not analysed" in err[0]
    verdict = np.load(out)["verdict"]
    done = verdict != -1
    assert done.sum() == 48  # the three whole chunks before the cut
    np.testing.assert_array_equal(verdict[done], np.where(closed, 2, 0)[:48])


@pytest.mark.parametrize("contact,want", [
    pytest.param("hard", 3, marks=pytest.mark.long), ("soft", 2)])  # hard: 7 s
def test_synthesize_a_mesh_with_the_default_fingers(contact, want, capsys):
    """`synthesize MESH` without --fingers takes the API's (and dataset's) default: the
    fewest that can hold a polyhedron, 3 hard or 2 soft (two hard fingers cannot resist
    rotation about the line between them), and says so in one line."""
    import pybullet_data

    from forceclosure.synthesis.best import synthesize

    mesh = str(Path(pybullet_data.getDataPath()) / "cube.obj")  # not written here
    assert synthesize(mesh, contact=contact, mu=0.5, top=1).fingers == want
    assert main(["synthesize", mesh, "--mu", "0.5", "--top", "1", "--contact", contact]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == (f"cube: by default {want} {contact} fingers, the fewest that can hold a "
                      f"polyhedron: " + ("two cannot resist rotation about the line between "
                                         "them" if contact == "hard" else
                                         "two soft fingers with friction can (§5.2)")
                      + " (--fingers N to choose)")
    assert out[1].startswith(f"cube: 1 best {want}-finger grasps")
    assert "certified: True" in out[3]


@pytest.mark.parametrize("argv,fingers,defaulted", [
    (["square"], 2, True),  # polygons: two fingers with friction, as before
    (["square", "--contact", "frictionless"], 4, True),  # the plane needs four without
    (["square", "--fingers", "2"], 2, False),  # an explicit --fingers: as before, no note
    (["square", "--fingers", "3", "--mu", "0.8"], 3, False),
])
def test_synthesize_default_fingers_on_polygons(argv, fingers, defaulted, capsys):
    from forceclosure.objects import bundled
    from forceclosure.synthesis.best import synthesize

    assert main(["synthesize", *argv, "--top", "1"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert (out[0].startswith(f"square: by default {fingers} ")) is defaulted
    assert out[int(defaulted)].startswith("square: ") and (
        f" best {fingers}-finger grasps" in out[int(defaulted)])
    if defaulted:
        contact = "frictionless" if "frictionless" in argv else "hard"
        assert synthesize(bundled("square"), contact=contact, top=1).fingers == fingers
    assert main(["synthesize", *argv, "--top", "1", "--json"]) == 0  # JSON: unchanged
    assert json.loads(capsys.readouterr().out)["fingers"] == fingers
