"""A dataset's records and results.parquet carry the units the object's file states (issue 25):
an SVG drawn in millimetres says ``mm`` (half-millimetre user units ``0.5 mm``), as
``synthesize`` says it; a file that states none (a GeoJSON without units, a mesh, a bundled
object) has null. The column is appended after every earlier one, and the table is read back."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd
import pyarrow.parquet as pq

from forceclosure.datasets import COLUMNS, Job, record_name, run_dataset

NS = 'xmlns="http://www.w3.org/2000/svg"'
PLATE = "M10 10 H90 V40 H60 V30 H40 V40 H10 Z"  # a U-shaped plate, 80 x 30 user units


def _svg(folder: Path, name: str, root: str) -> Path:
    path = folder / f"{name}.svg"
    path.write_text(f'<svg {NS} {root}><path d="{PLATE}"/></svg>')
    return path


def test_records_and_table_carry_the_files_units(tmp_path):
    # ground truth: the roots below state 1 mm and 0.5 mm a user unit (width over viewBox)
    mm = _svg(tmp_path, "mm", 'width="100mm" height="50mm" viewBox="0 0 100 50"')
    half = _svg(tmp_path, "half", 'width="100mm" viewBox="0 0 200 100"')
    plain = tmp_path / "plain.geojson"
    plain.write_text(json.dumps({"type": "Polygon", "coordinates": [
        [[10, 10], [90, 10], [90, 40], [10, 40], [10, 10]]]}))
    out = tmp_path / "out"
    summary = run_dataset([str(mm), str(half), str(plain), "cube"], out,
                          Job(contact="soft", mu=0.5, top=1), workers=1, progress=False,
                          log=lambda line: None)
    assert summary.done == 4
    records = {p.stem if isinstance(p, Path) else p: json.loads(
        (out / "objects" / record_name(Path(p))).read_text()) for p in (mm, half, plain, "cube")}
    assert [records[k]["units"] for k in ("mm", "half", "plain", "cube")] == [
        "mm", "0.5 mm", None, None]
    # both plates are 80 x 30 user units: the same numbers, in the units each record says
    # (85.4 mm across, and 85.4 units of 0.5 mm: 42.7 mm)
    for k in ("mm", "half"):
        assert abs(records[k]["size"] - math.hypot(80, 30)) < 1e-9 * 100

    path = out / "results.parquet"
    assert pq.read_schema(path).field("units").type == "string"
    table = pd.read_parquet(path).set_index("name")
    assert list(table.columns)[-1] == "units" and [n for n, _ in COLUMNS][-1] == "units"
    assert table.loc["mm", "units"] == "mm" and table.loc["half", "units"] == "0.5 mm"
    assert table.loc[["plain", "cube"], "units"].isna().all()  # null in the file
