import json
import subprocess
import sys
from importlib import resources
from pathlib import Path

import jsonschema
import pytest

from forceclosure.cli import main

DATA = Path(__file__).parent / "data"
SCHEMA = json.loads((Path(__file__).parents[1] / "docs" / "grasp-file.schema.json").read_text())
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
def test_bad_input_is_one_line_and_exit_2(name):
    proc = subprocess.run([sys.executable, "-m", "forceclosure.cli", "analyze",
                           str(DATA / "bad" / name)], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert "Traceback" not in proc.stderr
    assert EXPECTED[name] in lines[0], lines[0]


def test_missing_file_and_usage_errors(capsys):
    assert main(["analyze", "/no/such/file.json"]) == 2
    assert "no such file" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        main(["analyze"])
    assert e.value.code == 2


@pytest.mark.parametrize("script", sorted((Path(__file__).parents[1] / "examples").glob("*.py")))
def test_examples_run(script):
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "force-closure" in proc.stdout or "closure" in proc.stdout
