"""Synthesis datasets say whether each object's search is complete (issue 25): the records
carry ``complete`` and ``undecided`` as ``synthesize --json`` prints them, and
results.parquet has them as columns, appended after every earlier column."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from forceclosure.app.cli import main
from forceclosure.datasets import COLUMNS, Job, record_name, row_of, run_dataset
from forceclosure.synthesis import best

# an L of exact integer corners: at the origin Lemma 1 gives its three grasps for mu 0.4,
# every pair of edges decided; moved by 1e14 (accepted here by lowering the resolution
# synthesize asks for) doubles are 0.0156 apart and some sites cannot be proved
L_SHAPE = np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]], float)


def _write(folder: Path, name: str, offset: float) -> Path:
    ring = np.add(L_SHAPE, [offset, -offset]).tolist()
    path = folder / f"{name}.geojson"
    path.write_text(json.dumps({"type": "Polygon", "coordinates": [ring + ring[:1]]}))
    return path


def test_records_and_table_say_complete_and_undecided(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(best, "RESOLUTION", 1.0)  # workers=1: computed in this process
    near, far = _write(tmp_path, "near", 0.0), _write(tmp_path, "far", 1e14)
    job = Job(contact="hard", mu=0.4, top=3, margin=1e-10)  # 2 fingers on a polygon
    out = tmp_path / "out"
    summary = run_dataset([str(near), str(far), "cube"], out, job, workers=1, progress=False,
                          log=lambda line: None)
    assert summary.done == 3 and summary.incomplete == 1
    assert "not complete: 1 object with sites undecided" in str(summary)
    assert summary.to_dict()["incomplete"] == 1
    records = {p: json.loads((out / "objects" / record_name(p)).read_text())
               for p in (near, far)}
    # what synthesize --json says of the same files and options
    for path in (near, far):
        assert main(["synthesize", str(path), "--contact", "hard", "--mu", "0.4", "--top", "3",
                     "--margin", "1e-10", "--json"]) == 0
        cli = json.loads(capsys.readouterr().out)
        record = records[path]
        assert (record["complete"], record["undecided"]) == (cli["complete"], cli["undecided"])
        assert len(record["grasps"]) == len(cli["grasps"])
    assert records[near]["complete"] is True and records[near]["undecided"] == 0
    assert len(records[near]["grasps"]) == 3
    assert records[far]["complete"] is False and records[far]["undecided"] >= 1
    assert len(records[far]["grasps"]) < 3  # grasps were dropped, and it says so

    table = pd.read_parquet(out / "results.parquet").set_index("name")
    assert list(table.columns[-3:]) == ["complete", "undecided", "units"]  # units: appended
    assert bool(table.loc["near", "complete"]) and table.loc["near", "undecided"] == 0
    assert not table.loc["far", "complete"]
    assert table.loc["far", "undecided"] == records[far]["undecided"]
    cube = json.loads((out / "objects" / record_name(Path("cube"))).read_text())
    assert table.loc["cube", "complete"] == cube["complete"]
    assert table.loc["cube", "undecided"] == cube["undecided"]
    assert cube["fingers"] == 3 and cube["undecided"] == 0 and cube["complete"] is False


def test_older_records_read_with_the_columns_empty():
    """A record written before these keys: its row has them null, the other columns as
    before and in their places."""
    names = [name for name, _ in COLUMNS]
    assert names.index("labels_file") == len(names) - 4  # appended after the last column
    old = {"name": "x", "path": "/x", "status": "done", "error": None, "fingers": 2,
           "grasps": [], "kind": "polygon"}
    row = row_of(old)
    assert row["complete"] is None and row["undecided"] is None and row["units"] is None
    assert row["grasps"] == 0 and row["fingers"] == 2
