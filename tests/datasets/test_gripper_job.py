"""``forceclosure dataset --gripper parallel-jaw``: labelled jaw poses over object sets.

Checked against truth computed here: the cube's opposite-face pinches
(closure iff the jaws' line is inside the friction cone, μ* = tan of its
tilt, Corollary 3), contacts on a pybullet_data mesh's surface as trimesh
measures it, the documented per-object seed recomputed from its formula,
and the tables read back with pandas and NumPy."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pybullet_data
import pytest
import trimesh

from forceclosure.app.cli import main
from forceclosure.datasets import GRASP_COLUMNS, GripperJob, fingerprint, record_name, run_dataset
from forceclosure.gripper.jaw import ParallelJaw
from forceclosure.gripper.labels import grasp_labels
from forceclosure.objects.io import load_object

DATA = Path(pybullet_data.getDataPath())
MESH = DATA / "random_urdfs" / "000" / "000.obj"  # 6 x 8 x 2.1, closed
WIDTH, MU, COUNT, SEED = 4.0, 0.5, 60, 7
ARGS = ["--gripper", "parallel-jaw", "--width", str(WIDTH), "--mu", str(MU), "--count",
        str(COUNT), "--seed", str(SEED)]
JOB = GripperJob(width=WIDTH, mu=MU, count=COUNT, seed=SEED)
ARRAYS = ("center", "closing_axis", "approach_axis", "width", "points", "normals", "code",
          "least_friction", "epsilon", "collides")


def documented_seed(seed: int, path) -> int:
    """docs/datasets.md: the first 63 bits of SHA-256("<seed>:<fingerprint>"), big-endian."""
    digest = hashlib.sha256(f"{seed}:{fingerprint(path, JOB)}".encode()).digest()
    return int.from_bytes(digest[:8], "big") >> 1


def _npz(out: Path, path) -> dict[str, np.ndarray]:
    name = record_name(Path(path)).removesuffix(".json") + ".npz"
    with np.load(out / "objects" / name) as z:
        return {k: z[k] for k in z.files}


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("gripper") / "out"
    status = main(["dataset", "cube", "l-prism", str(MESH), "--out", str(out), *ARGS,
                   "--workers", "1"])
    return status, out


def test_tables_equal_the_label_files(run):
    status, out = run
    assert status == 0
    objects = pd.read_parquet(out / "results.parquet")
    assert sorted(objects.name) == ["000", "cube", "l-prism"]
    assert (objects.status == "done").all() and (objects.grasps == COUNT).all()
    assert (objects.closure + objects.marginal + objects.none == COUNT).all()
    grasps = pd.read_parquet(out / "grasps.parquet")
    assert list(grasps.columns) == [name for name, _ in GRASP_COLUMNS]
    assert len(grasps) == 3 * COUNT
    for path in ("cube", "l-prism", str(MESH)):
        row = objects[objects.name == Path(path).stem].iloc[0]
        z = _npz(out, path)
        g = grasps[grasps.path == row.path]
        assert g.grasp.tolist() == list(range(COUNT))
        for key in ("center", "closing_axis", "approach_axis"):
            assert np.array_equal(g[[f"{key}_{a}" for a in "xyz"]].to_numpy(), z[key])
        for jaw in (1, 2):
            assert np.array_equal(g[[f"point{jaw}_{a}" for a in "xyz"]].to_numpy(),
                                  z["points"][:, jaw - 1])
            assert np.array_equal(g[[f"normal{jaw}_{a}" for a in "xyz"]].to_numpy(),
                                  z["normals"][:, jaw - 1])
        assert np.array_equal(g.width.to_numpy(), z["width"])
        assert np.array_equal(g.least_friction.to_numpy(), z["least_friction"])
        assert np.array_equal(g.epsilon.to_numpy(), z["epsilon"])
        assert np.array_equal(g.collides.to_numpy(dtype=bool), z["collides"])
        names = {0: "none", 1: "marginal", 2: "closure"}
        assert g.verdict.tolist() == [names[c] for c in z["code"].tolist()]
        # the summary row counts what the file holds
        assert row.closure == int(np.sum(z["code"] == 2))
        assert row.collides == int(z["collides"].sum())
        assert row.closure_clear == int(np.sum((z["code"] == 2) & ~z["collides"]))
        assert row.seed == documented_seed(SEED, path)
        assert json.loads(str(z["meta"]))["seed"] == row.seed


def test_labels_equal_a_direct_call_with_the_documented_seed(run):
    _, out = run
    seeds = set()
    for path in ("cube", "l-prism", str(MESH)):
        seed = documented_seed(SEED, path)
        seeds.add(seed)
        direct = grasp_labels(load_object(path), ParallelJaw(WIDTH), MU, COUNT, seed, "soft")
        z = _npz(out, path)
        for key in ARRAYS:
            assert np.array_equal(getattr(direct, key), z[key], equal_nan=True), key
    assert len(seeds) == 3


def test_cube_pinches_against_the_friction_cone(run):
    """Contacts on opposite faces of the cube [-1, 1]^3, normals antiparallel: closure iff
    the jaws' line is tilted from the faces' normal by less than atan(mu), and then the
    least friction is tan(tilt) (Corollary 3)."""
    _, out = run
    z = _npz(out, "cube")
    p, n = z["points"], z["normals"]
    # every contact on the cube's surface, with the face's outward normal
    axis = np.argmax(np.abs(p), axis=2)
    np.testing.assert_allclose(np.abs(p).max(axis=2), 1.0, atol=1e-9)
    expected = np.zeros_like(n)
    for i in range(len(p)):
        for j in range(2):
            expected[i, j, axis[i, j]] = np.sign(p[i, j, axis[i, j]])
    np.testing.assert_allclose(n, expected, atol=1e-12)
    np.testing.assert_allclose(z["width"], np.linalg.norm(p[:, 1] - p[:, 0], axis=1),
                               rtol=1e-9)
    opposite = (axis[:, 0] == axis[:, 1]) & (np.sum(n[:, 0] * n[:, 1], axis=1) < -0.999)
    assert opposite.sum() >= 10
    checked = 0
    for i in np.flatnonzero(opposite):
        d = p[i, 1] - p[i, 0]
        tilt = np.arccos(abs(d[axis[i, 0]]) / np.linalg.norm(d))
        if abs(tilt - np.arctan(MU)) < 1e-6:
            continue  # on the cone's boundary: marginal either way
        assert (z["code"][i] == 2) == (tilt < np.arctan(MU))
        assert z["least_friction"][i] == pytest.approx(np.tan(tilt), abs=2e-4)
        checked += 1
    assert checked >= 10


def test_mesh_contacts_on_its_surface(run):
    _, out = run
    z = _npz(out, MESH)
    mesh = trimesh.load(MESH, force="mesh")
    _, distance, triangle = trimesh.proximity.closest_point(mesh, z["points"].reshape(-1, 3))
    assert distance.max() < 1e-9 * mesh.scale
    # normals: the outward normals of the faces the contacts lie on
    normals = mesh.face_normals[triangle].reshape(-1, 2, 3)
    assert np.min(np.sum(normals * z["normals"], axis=2)) > 1 - 1e-6


def test_rerun_skips_and_a_changed_input_is_redone(tmp_path, capsys):
    folder = tmp_path / "in"
    folder.mkdir()
    a, b = folder / "a.obj", folder / "b.obj"
    shutil.copy(MESH, a)
    shutil.copy(MESH, b)
    b.write_text(b.read_text() + "\n# edited\n")  # same shape, another file
    out = tmp_path / "out"
    first = run_dataset([folder], out, JOB, workers=1, progress=False)
    assert (first.done, first.computed) == (2, 2)
    files = {f.name: f.read_bytes() for f in (out / "objects").iterdir()}
    assert len(files) == 4
    table = (out / "grasps.parquet").read_bytes()
    # distinct files: distinct seeds, other samples
    assert not np.array_equal(_npz(out, a)["center"], _npz(out, b)["center"])
    again = run_dataset([folder], out, JOB, workers=1, progress=False)
    assert (again.computed, again.skipped) == (0, 2)
    assert {f.name: f.read_bytes() for f in (out / "objects").iterdir()} == files
    assert (out / "grasps.parquet").read_bytes() == table
    # the same command through the CLI: nothing to do, still exit 0
    assert main(["dataset", str(folder), "--out", str(out), *ARGS, "--workers", "1"]) == 0
    assert "2 skipped" in capsys.readouterr().out
    # editing a: a alone is redone, with its new seed
    a.write_text(a.read_text() + "\n# edited too\n")
    lines: list[str] = []
    third = run_dataset([folder], out, JOB, workers=1, progress=False, log=lines.append)
    assert (third.computed, third.skipped) == (1, 1)
    assert any("its input changed" in line for line in lines)
    meta = json.loads(str(_npz(out, a)["meta"]))
    assert meta["seed"] == documented_seed(SEED, a)
    name_b = record_name(b)
    before_b = _npz(out, b)
    assert (out / "objects" / name_b).read_bytes() == files[name_b]
    grasps = pd.read_parquet(out / "grasps.parquet")
    assert np.array_equal(grasps[grasps.path == str(a.resolve())][
        [f"center_{x}" for x in "xyz"]].to_numpy(), _npz(out, a)["center"])
    # a labels file deleted or changed behind the record's back: redone, with a warning
    (out / "objects" / record_name(a).replace(".json", ".npz")).unlink()
    npz_b = out / "objects" / name_b.replace(".json", ".npz")
    npz_b.write_bytes(npz_b.read_bytes()[:-10] + b"0123456789")
    lines.clear()
    fourth = run_dataset([folder], out, JOB, workers=1, progress=False, log=lines.append)
    assert (fourth.computed, fourth.done) == (2, 2)
    assert any("is missing" in line for line in lines)
    assert any("changed since" in line for line in lines)
    redone = _npz(out, b)
    assert all(np.array_equal(redone[k], before_b[k]) for k in ARRAYS)


@pytest.mark.parametrize("argv, message", [
    (["--gripper", "parallel-jaw", "--width", "3", "--mu", "0.5", "--fingers", "2"],
     "--fingers is for regions"),
    (["--gripper", "parallel-jaw", "--width", "3", "--mu", "0.5", "--top", "5"],
     "--top is for regions"),
    (["--gripper", "parallel-jaw", "--width", "3", "--mu", "0.5", "--analyze"],
     "--analyze is for regions"),
    (["--gripper", "parallel-jaw", "--mu", "0.5"], "needs --width"),
    (["--gripper", "parallel-jaw", "--width", "3"], "needs --mu"),
    (["--gripper", "parallel-jaw", "--width", "3", "--mu", "0.5", "--contact",
      "frictionless"], "soft or hard"),
    (["--gripper", "parallel-jaw", "--width", "-1", "--mu", "0.5"], "--width must be"),
    (["--gripper", "parallel-jaw", "--width", "3", "--mu", "0.5", "--count", "0"],
     "--count must be"),
    (["--width", "3"], "--width is for --gripper"),
    (["--mu", "0.5", "--count", "10"], "--count is for --gripper"),
    (["--gripper", "two-finger", "--width", "3", "--mu", "0.5"],
     "unknown gripper 'two-finger'"),
])
def test_refusals(tmp_path, capsys, argv, message):
    out = tmp_path / "out"
    try:
        status = main(["dataset", "cube", "--out", str(out), *argv])
    except SystemExit as e:  # argparse's own refusals
        status = e.code
    err = capsys.readouterr().err
    assert status == 2 and message in err and err.count("\n") == 1, err
    assert not out.exists()


def test_polygons_fail_alone_and_another_job_is_refused(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["dataset", "cube", "square", "--out", str(out), *ARGS, "--count", "5",
                 "--workers", "1"]) == 2
    captured = capsys.readouterr()
    assert "failed: square: a polygon; a parallel-jaw gripper grasps meshes" in captured.err
    objects = pd.read_parquet(out / "results.parquet")
    statuses = dict(zip(objects.name, objects.status, strict=True))
    assert statuses == {"cube": "done", "square": "failed"}
    assert len(pd.read_parquet(out / "grasps.parquet")) == 5
    # another width in the same folder: refused in one line, nothing changed
    assert main(["dataset", "cube", "--out", str(out), *ARGS, "--count", "5", "--width",
                 "5"]) == 2
    err = capsys.readouterr().err
    assert "holds results of another job (width 4.0 there, 5.0 here)" in err
    assert err.count("\n") == 1
    # and a region job too
    assert main(["dataset", "cube", "--out", str(out), "--contact", "soft"]) == 2
    assert "holds results of another job" in capsys.readouterr().err


@pytest.mark.long
def test_killed_run_resumes(tmp_path):
    """The command killed mid-way with its pool (SIGKILL), then run again: one record and
    one labels file per object, equal to a single-process run's, no temporary files."""
    from test_faults import _strip, _tmp_files, _urdfs, _wait_for

    inputs = [str(p) for p in _urdfs(8)]
    out = tmp_path / "killed"
    argv = [sys.executable, "-m", "forceclosure", "dataset", *inputs, "--out", str(out),
            *ARGS, "--count", "400", "--workers", "2"]
    run = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                           start_new_session=True)
    try:
        _wait_for(lambda: len(list((out / "objects").glob("*.json"))) >= 2, 240)
    finally:
        os.killpg(run.pid, signal.SIGKILL)
        run.wait()
    partial = {f.name: f.read_bytes() for f in (out / "objects").glob("*.json")}
    assert 2 <= len(partial) < 8
    done = subprocess.run(argv, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert f"{len(partial)} skipped" in done.stdout
    assert all((out / "objects" / n).read_bytes() == b for n, b in partial.items())
    assert _tmp_files(out) == []
    truth = tmp_path / "truth"
    job = GripperJob(width=WIDTH, mu=MU, count=400, seed=SEED)
    run_dataset(inputs, truth, job, workers=1, progress=False)
    for f in (truth / "objects").glob("*.json"):
        mine = json.loads((out / "objects" / f.name).read_text())
        theirs = json.loads(f.read_text())
        # the labels files' bytes differ by their zip timestamps only: compare arrays
        mine.pop("labels_sha256"), theirs.pop("labels_sha256")
        assert _strip(mine) == _strip(theirs)
    assert pd.read_parquet(out / "grasps.parquet").equals(
        pd.read_parquet(truth / "grasps.parquet"))


@pytest.mark.long
def test_time_limit_on_the_pool_then_retry(tmp_path):
    """An object over the time limit on the local pool is recorded as 'timeout', with no
    labels file and no rows; --retry-failed with room to spare labels it, and the rows
    then equal its labels file."""
    out = tmp_path / "out"
    # 3,000 poses with epsilon: far over 0.05 s, and a retry that takes seconds, not minutes
    slow = GripperJob(width=WIDTH, mu=MU, count=3_000, seed=SEED, timeout=0.05)
    first = run_dataset(["cube", str(MESH)], out, slow, workers=2, progress=False,
                        log=lambda line: None)
    assert first.timeout >= 1
    objects = pd.read_parquet(out / "results.parquet")
    late = objects[objects.status == "timeout"]
    assert late.labels_file.isna().all()
    assert not set(late.path) & set(pd.read_parquet(out / "grasps.parquet").path)
    npz = list((out / "objects").glob("*.npz"))
    assert len(npz) == first.done
    again = run_dataset(["cube", str(MESH)], out, GripperJob(width=WIDTH, mu=MU, count=3_000,
                                                             seed=SEED),
                        workers=2, progress=False, retry_failed=True)
    assert (again.done, again.computed) == (2, first.timeout)
    grasps = pd.read_parquet(out / "grasps.parquet")
    z = _npz(out, MESH)
    mine = grasps[grasps.path == str(MESH.resolve())]
    assert np.array_equal(mine.epsilon.to_numpy(), z["epsilon"]) and len(mine) == 3_000
