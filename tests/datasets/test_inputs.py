"""``dataset --out`` inside an input folder, and a damaged ``job.json`` (issue 28, items 5).

The inputs are two polygons written here (a right triangle and a unit square, as CSV),
synthesised with two soft fingers: a few milliseconds each, in this process.
"""

import json

import pandas as pd
import pytest

from forceclosure.app.cli import main
from forceclosure.datasets import expand_inputs

ARGS = ["--contact", "soft", "--mu", "0.5", "--top", "1", "--workers", "1", "--json"]


@pytest.fixture
def inputs(tmp_path):
    folder = tmp_path / "objects"
    folder.mkdir()
    (folder / "triangle.csv").write_text("x,y\n0,0\n3,0\n0,3\n")
    (folder / "square.csv").write_text("x,y\n0,0\n1,0\n1,1\n0,1\n")
    return folder


def run(argv, capsys):
    status = main(argv)
    captured = capsys.readouterr()
    return status, (json.loads(captured.out) if captured.out else None), captured.err


def test_out_inside_the_input_folder_twice(inputs, capsys):
    """The second run finds the same two objects (its job.json and records are not taken
    as polygons), and skips both; the table holds the two objects only."""
    out = inputs / "results"
    argv = ["dataset", str(inputs), "--out", str(out), *ARGS]
    status, first, _ = run(argv, capsys)
    assert status == 0 and (first["objects"], first["done"], first["computed"]) == (2, 2, 2)
    assert (out / "job.json").is_file() and len(list((out / "objects").glob("*.json"))) == 2
    status, second, err = run(argv, capsys)
    assert status == 0, err
    assert (second["objects"], second["skipped"], second["computed"]) == (2, 2, 0)
    table = pd.read_parquet(out / "results.parquet")
    assert sorted(table["name"]) == ["square", "triangle"]
    # a glob pattern over the folder leaves the results out too
    assert [p.name for p in expand_inputs([str(inputs / "**" / "*.*")], exclude=out)] == [
        "square.csv", "triangle.csv"]


def test_truncated_job_file_is_rebuilt_from_the_records(inputs, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["dataset", str(inputs), "--out", str(out), *ARGS]
    assert run(argv, capsys)[0] == 0
    job = (out / "job.json").read_text()
    (out / "job.json").write_text(job[: len(job) // 2])  # cut mid-write
    status, summary, err = run(argv, capsys)
    assert status == 0 and (summary["skipped"], summary["computed"]) == (2, 0)  # nothing lost
    assert "job.json: damaged; rebuilt from the job its" in err
    assert json.loads((out / "job.json").read_text()) == json.loads(job)
    # rebuilt as the records say, so another job is still refused
    (out / "job.json").write_text("{")
    status, _, err = run([*argv[:4], "--contact", "soft", "--mu", "0.7", *ARGS[4:]], capsys)
    assert status == 2 and "holds results of another job (mu 0.5 there, 0.7 here)" in err
    assert json.loads((out / "job.json").read_text()) == json.loads(job)


def test_damaged_job_file_with_records_of_two_jobs_is_refused(inputs, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["dataset", str(inputs), "--out", str(out), *ARGS]
    assert run(argv, capsys)[0] == 0
    record = next((out / "objects").glob("*.json"))
    data = json.loads(record.read_text())
    data["job"] = {**data["job"], "mu": 0.9}
    record.write_text(json.dumps(data))
    (out / "job.json").write_text("not json")
    status, _, err = run(argv, capsys)
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1
    assert "damaged, and the records in" in lines[0] and "belong to 2 jobs" in lines[0]
    assert "remove job.json" in lines[0] and "another --out" in lines[0]
    (out / "job.json").unlink()  # the way out it names: this job's records are kept
    status, summary, _ = run(argv, capsys)
    assert status == 0 and (summary["skipped"], summary["computed"]) == (1, 1)


def test_out_as_a_parent_of_the_inputs(inputs, tmp_path, capsys):
    """``--out`` a folder holding the inputs: only the dataset's own files are left out, so
    both polygons are found, computed, then skipped on the second run."""
    out = tmp_path / "x"
    out.mkdir()
    inputs = inputs.rename(out / "meshes")
    argv = ["dataset", str(inputs), "--out", str(out), *ARGS]
    status, first, err = run(argv, capsys)
    assert status == 0, err
    assert (first["objects"], first["done"], first["computed"]) == (2, 2, 2)
    status, second, err = run(argv, capsys)
    assert status == 0 and (second["objects"], second["skipped"], second["computed"]) == (
        2, 2, 0), err
    table = pd.read_parquet(out / "results.parquet")
    assert sorted(table["name"]) == ["square", "triangle"]
    # the whole parent, walked: its own job.json and records are still left out
    assert [p.name for p in expand_inputs([str(out)], exclude=out)] == [
        "square.csv", "triangle.csv"]


def test_the_jobs_output_folders_are_left_out(inputs, tmp_path):
    """The folders the job writes (pictures, exports) are not read as objects either."""
    pictures = inputs / "pictures"
    pictures.mkdir()
    (pictures / "stray.csv").write_text("x,y\n0,0\n1,0\n0,1\n")
    names = sorted(p.name for p in expand_inputs([str(inputs)], exclude=tmp_path / "out"))
    assert names == ["square.csv", "stray.csv", "triangle.csv"]
    names = [p.name for p in expand_inputs([str(inputs)], exclude=tmp_path / "out",
                                            folders=[pictures])]
    assert names == ["square.csv", "triangle.csv"]
