"""Exports read back by readers written here from the documented formats.

graspnetAPI's GraspGroup array is parsed column by column as graspnetAPI's
``Grasp`` reads it (score, width, height, depth, R row-major, translation,
object id) and its pose is checked against graspnetAPI's gripper geometry
(fingers at ``y = ∓width/2`` of the grasp frame, along its x axis): the
fingers' inner faces must land on the contacts that the ray casting found
(saved in the labels file). ACRONYM's HDF5 is read the way its
``load_grasps``/``load_mesh`` read it (plain h5py), and the jaw centre and
closing axis recovered from the 4x4 transforms (x closing, z approach,
origin ``offset`` behind the centre) must give the same contacts.
"""

import json
import sys

import h5py
import numpy as np
import pytest

from forceclosure.app.cli import main

ARGS = ["grasps", "cube", "--width", "2.2", "--count", "60", "--seed", "3",
        "--clearance", "0.1"]


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    d = tmp_path_factory.mktemp("export")
    paths = {"labels": d / "l.npz", "graspnet": d / "g.npy", "acronym": d / "a.h5",
             "epsilon": d / "e.npy"}
    assert main([*ARGS, "--out", str(paths["labels"]), "--json",
                 "--export", "graspnet", str(paths["graspnet"]),
                 "--export", "acronym", str(paths["acronym"])]) == 0
    assert main([*ARGS, "--json", "--graspnet-score", "epsilon",
                 "--export", "graspnet", str(paths["epsilon"])]) == 0
    with np.load(paths["labels"]) as saved:
        labels = {name: saved[name] for name in saved.files}
    return paths, labels


def _accepted(labels):
    return (labels["code"] == 2) & ~labels["collides"]


def test_graspnet_array_read_back(exported):
    paths, labels = exported
    rows = np.load(paths["graspnet"])
    assert rows.shape == (60, 17) and rows.dtype == np.float64
    score, width, height, depth = rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3]
    R = rows[:, 4:13].reshape(-1, 3, 3)  # graspnetAPI: grasp_array[4:13].reshape((3, 3))
    t, object_id = rows[:, 13:16], rows[:, 16]
    np.testing.assert_allclose(np.einsum("nji,njk->nik", R, R), np.broadcast_to(np.eye(3),
                               R.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
    # graspnetAPI's gripper: fingers along +x (the approach), at y = -w/2 and +w/2
    np.testing.assert_allclose(R[:, :, 0], labels["approach_axis"], atol=1e-12)
    # each contact on its finger's inner face (a pad's first touch may lie off the jaws'
    # line): y = -w/2, +w/2 in the grasp frame, x from the finger's base to its tip at
    # x = depth, |z| within half the height
    for jaw, side in ((0, -1), (1, 1)):
        q = np.einsum("nji,nj->ni", R, labels["points"][:, jaw] - t)
        np.testing.assert_allclose(q[:, 1], side * width / 2, atol=1e-9)
        assert np.all((q[:, 0] <= depth + 1e-9) & (q[:, 0] >= depth - 1.1 - 1e-9))
        assert np.all(np.abs(q[:, 2]) <= height / 2 + 1e-9)
    np.testing.assert_allclose(t, labels["center"], atol=1e-12)
    # the default hand: height 0.2 w, depth 0.2 w (w = 2.2), or the pose's own depth
    np.testing.assert_allclose(height, 0.44)
    np.testing.assert_allclose(depth, labels.get("depth", 0.44))
    assert np.all(object_id == -1)
    ok = _accepted(labels)
    assert 0 < ok.sum() < len(ok)
    np.testing.assert_allclose(score[ok], 1.1 - labels["least_friction"][ok])
    assert np.all(score[~ok] == -1) and np.all(score[ok] > 0.1)  # mu* < mu = 0.3 here
    eps = np.load(paths["epsilon"])[:, 0]
    np.testing.assert_allclose(eps[ok], labels["epsilon"][ok])
    assert np.all(eps[~ok] == -1)


def test_acronym_file_read_back(exported):
    paths, labels = exported
    with h5py.File(paths["acronym"], "r") as data:  # as acronym_tools' load_grasps reads it
        T = np.array(data["grasps/transforms"])
        success = np.array(data["grasps/qualities/flex/object_in_gripper"])
        mesh_file = data["object/file"][()].decode("utf-8")
        scale = data["object/scale"][()]
        offset = data["gripper/offset"][()]
        ours = {name: np.array(data["forceclosure"][name]) for name in data["forceclosure"]}
        meta = json.loads(data["forceclosure"].attrs["meta"])
    assert T.shape == (60, 4, 4) and success.dtype == np.int64
    # a bundled object is no file: its surface is written beside the .h5, in its units
    assert mesh_file == "a.obj" and scale == 1.0
    assert (paths["acronym"].parent / "a.obj").is_file()
    # the default origin: the hand's base, the fingertips finger_length + palm = 0.6 w ahead
    # of it, each pose's tips its depth (default 0.2 w) past the jaw centre
    tip, depth = 0.6 * 2.2, labels.get("depth", np.full(60, 0.2 * 2.2))
    assert offset == pytest.approx(tip - 0.2 * 2.2)
    np.testing.assert_allclose(T[:, 3], np.broadcast_to([0, 0, 0, 1.0], (60, 4)))
    closing, approach = T[:, :3, 0], T[:, :3, 2]  # ACRONYM: x closing, z approach
    center = T[:, :3, 3] + (tip - depth)[:, None] * approach
    np.testing.assert_allclose(np.cross(approach, closing), T[:, :3, 1], atol=1e-12)
    np.testing.assert_allclose(center, labels["center"], atol=1e-12)
    np.testing.assert_allclose(closing, labels["closing_axis"], atol=1e-12)
    for jaw, side in ((0, -1), (1, 1)):  # on the finger's inner face, between base and tip
        q = np.einsum("nji,nj->ni", T[:, :3, :3], labels["points"][:, jaw] - T[:, :3, 3])
        np.testing.assert_allclose(q[:, 0], side * labels["width"] / 2, atol=1e-9)
        assert np.all((q[:, 2] <= tip + 1e-9) & (q[:, 2] >= tip - 1.1 - 1e-9))
        assert np.all(np.abs(q[:, 1]) <= 0.22 + 1e-9)
    assert success.tolist() == _accepted(labels).astype(int).tolist()
    assert ours["collides"].tolist() == labels["collides"].tolist()
    assert [v.decode() for v in ours["verdict"]] == [["none", "marginal", "closure"][c]
                                                     for c in labels["code"]]
    assert meta["mu"] == 0.3 and meta["collision"]["clearance"] == 0.1


def test_bad_exports_are_refused_before_any_work(tmp_path, capsys):
    target = tmp_path / "g.npy"
    cases = [(["--export", "dexnet", str(target)], "unknown kind 'dexnet'"),
             (["--export", "graspnet", str(tmp_path / "g.h5")], "written as .npy"),
             (["--export", "acronym", str(tmp_path / "a.npy")], "written as .h5 or .hdf5"),
             (["--export", "graspnet", str(target), "--no-least-friction"], "--graspnet-score"),
             (["--export", "graspnet", str(tmp_path / "no" / "g.npy")], "g.npy"),
             (["--export", "graspnet", str(target), "--export", "graspnet", str(target)],
              "own file")]
    for extra, words in cases:
        assert main(["grasps", "cube", "--width", "3", "--count", "100000", *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and words in err, err
    assert not target.exists()


def test_missing_h5py_names_the_extra(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py raises ImportError
    assert main(["grasps", "cube", "--width", "3", "--count", "100000",
                 "--export", "acronym", str(tmp_path / "a.h5")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "'export' extra" in err


def test_library_refusals():
    from forceclosure.errors import InputError
    from forceclosure.gripper.jaw import ParallelJaw
    from forceclosure.gripper.labels import grasp_labels
    from forceclosure.io.export import graspnet_array

    labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=10, least_friction=False,
                          collision=False)
    assert labels.counts()["closure"] > 0
    with pytest.raises(InputError, match="least friction"):
        graspnet_array(labels)
    with pytest.raises(InputError, match="score must be"):
        graspnet_array(labels, score="q1")
    # epsilon needs no least friction; closure without a collision check is accepted
    scores = graspnet_array(labels, score="epsilon")[:, 0]
    closed = labels.code == 2
    np.testing.assert_allclose(scores[closed], labels.epsilon[closed])
    assert np.all(scores[~closed] == -1)
