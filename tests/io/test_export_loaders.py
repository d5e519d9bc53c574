"""Exports read by the tools' own loading code, and saved labels read back.

* graspnetAPI 1.2.11's own ``GraspGroup().from_npy`` reads the ``.npy`` (CI installs it
  with ``uv pip install --no-deps``: it pins numpy 1.20 and imports open3d and cv2 when its
  package loads; the heavy modules that ``graspnetAPI.grasp`` does not use are stubbed).
  Its translations, rotations, widths, depths, heights and scores must be the labels',
  and its gripper frame (fingers along +x at ``y = ∓width/2``) must put the fingers on
  the contacts.
* ACRONYM's ``acronym_tools`` is not on PyPI: its loading path is written out here as
  ``load_mesh`` and ``load_grasps`` read an ``.h5`` (``trimesh.load(os.path.join(root,
  object/file)).apply_scale(object/scale)``; ``grasps/transforms``,
  ``grasps/qualities/flex/object_in_gripper``). The loaded mesh must be the object the
  labels were made on (the contacts on its surface, the two surfaces on each other), and
  the transforms must put the Panda's fingers (``create_gripper_marker``: x = ±0.041,
  z from 0.066 to the tips at 0.11217) on the contacts.
"""

import dataclasses
import hashlib
import importlib
import importlib.util
import json
import os
import sys
import types
from types import SimpleNamespace

import h5py
import numpy as np
import pybullet_data
import pytest
import trimesh

from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.gripper.jaw import ParallelJaw
from forceclosure.gripper.labels import (
    ARRAYS,
    METRIC_ARRAYS,
    ROBUST_ARRAYS,
    TASK_ARRAYS,
    GraspLabels,
    grasp_labels,
)
from forceclosure.io.export import graspnet_array, save_acronym, save_graspnet
from forceclosure.objects.io import load_object

DATA = pybullet_data.getDataPath()
DUCK = os.path.join(DATA, "duck_vhacd.urdf")
#: ACRONYM's Panda (acronym_tools.acronym.create_gripper_marker): the fingers' segments
PANDA_X, PANDA_BASE, PANDA_TIP = 0.041, 0.066, 0.11217


# -- the tools' loading code -------------------------------------------------------------

def acronym_load_mesh(h5, mesh_root):
    """acronym_tools.acronym.load_mesh's path for an .h5."""
    with h5py.File(h5, "r") as data:
        name = data["object/file"][()].decode("utf-8")
        scale = data["object/scale"][()]
    return trimesh.load(os.path.join(mesh_root, name)).apply_scale(scale), name, scale


def acronym_load_grasps(h5):
    """acronym_tools.acronym.load_grasps for an .h5."""
    with h5py.File(h5, "r") as data:
        return (np.array(data["grasps/transforms"]),
                np.array(data["grasps/qualities/flex/object_in_gripper"]))


@pytest.fixture
def graspnet_grasp(monkeypatch):
    """graspnetAPI.grasp, imported without the package's __init__ (which loads the whole
    dataset toolkit) and with the missing heavy modules it names stubbed."""
    spec = importlib.util.find_spec("graspnetAPI")
    if spec is None:
        pytest.skip("graspnetAPI not installed (CI: uv pip install --no-deps "
                    "graspnetAPI==1.2.11)")

    def stub(name, package=False):
        module = types.ModuleType(name)
        if package:
            module.__path__ = []

        def missing(attr):
            def unavailable(*args, **kwargs):
                raise RuntimeError(f"{name}.{attr} is stubbed in this test")
            return unavailable
        module.__getattr__ = missing
        return module

    package = types.ModuleType("graspnetAPI")
    package.__path__ = list(spec.submodule_search_locations)
    monkeypatch.setitem(sys.modules, "graspnetAPI", package)
    for name in ("open3d", "cv2"):
        if importlib.util.find_spec(name) is None:
            monkeypatch.setitem(sys.modules, name, stub(name))
    if importlib.util.find_spec("transforms3d") is None:
        for name in ("transforms3d", "transforms3d.euler", "transforms3d.quaternions"):
            monkeypatch.setitem(sys.modules, name, stub(name, package=name == "transforms3d"))
    yield importlib.import_module("graspnetAPI.grasp")
    for name in [n for n in sys.modules if n.startswith("graspnetAPI.")]:
        del sys.modules[name]


# -- the labels ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def duck():
    """30 jaw poses on pybullet_data's duck (the URDF scales duck_vhacd.obj by 0.05), a
    Panda-sized opening; the collision check is left out (closure alone is accepted)."""
    obj = load_object(DUCK)
    labels = grasp_labels(obj, ParallelJaw(0.08), mu=0.5, count=30, seed=1, collision=False)
    assert 0 < labels.counts()["closure"] < len(labels)
    return obj, labels


def with_meta_and_depth(labels, depth=None, **meta):
    """The labels with ``meta`` entries added and, optionally, a per-pose ``depth`` (the
    contract's optional array), as an object with the same attributes."""
    fields = {**vars(labels), "meta": {**labels.meta, **meta}}
    if depth is not None:
        fields["depth"] = np.asarray(depth, dtype=float)
    return SimpleNamespace(**fields)


def along_approach(labels):
    """``(N, 2)``: each contact's distance past its jaw centre along the approach axis (0
    for contacts on the jaws' line; anywhere on a pad for a pad's first touch)."""
    return np.einsum("nkj,nj->nk", labels.points - labels.center[:, None],
                     labels.approach_axis)


def depths_reaching_past(labels, seed, pad_length=0.04):
    """Per-pose depths that keep both contacts on the pads (``pad_length`` long, ending at
    the tips): between the farther contact and the nearer one plus the pad's length."""
    past = along_approach(labels)
    low, high = past.max(axis=1), past.min(axis=1) + pad_length
    assert np.all(low < high)
    return low + np.random.default_rng(seed).uniform(0.05, 0.95, len(labels)) * (high - low)


def saved_depth(labels, default):
    depth = getattr(labels, "depth", None)
    return np.full(len(labels.code), default) if depth is None else np.asarray(depth)


def in_frame(T, points):
    """Points ``(N, 3)`` in the frames of the poses ``T`` ``(N, 4, 4)``."""
    return np.einsum("nji,nj->ni", T[:, :3, :3], points - T[:, :3, 3])


def surface_distance(mesh, points):
    return trimesh.proximity.closest_point(mesh, points)[1]


# -- GraspLabels.load ---------------------------------------------------------------------

def _random_labels(n=7, seed=0):
    rng = np.random.default_rng(seed)
    arrays = {name: rng.normal(size=(n, 3)) for name in ("center", "closing_axis",
                                                         "approach_axis")}
    arrays.update(width=rng.random(n), points=rng.normal(size=(n, 2, 3)),
                  normals=rng.normal(size=(n, 2, 3)), code=rng.integers(0, 3, n).astype(np.int8),
                  least_friction=np.r_[np.inf, np.nan, rng.random(n - 2)],
                  epsilon=np.r_[np.nan, rng.random(n - 1)], collides=rng.random(n) < 0.5)
    names = {f.name for f in dataclasses.fields(GraspLabels)}  # "depth" once it is a field
    optional = {name: rng.random(n) for name in (*ROBUST_ARRAYS, *METRIC_ARRAYS,
                                                 *TASK_ARRAYS, "depth") if name in names}
    optional["task_verdict"] = rng.integers(0, 3, n).astype(np.int8)
    optional["torsion"] = rng.random((n, 2))  # one a pad
    if "robust_missed" in optional:
        optional["robust_missed"] = rng.integers(0, 9, n).astype(np.int64)
    meta = {"object": "x", "mu": 0.4, "width_max": 0.08, "collision": None,
            "rejected": {"why": 3}, "tip_offset": 0.1}
    return GraspLabels(**arrays, **optional, meta=meta)


def test_saved_labels_read_back_whole(tmp_path):
    labels = _random_labels()
    path = tmp_path / "l.npz"
    labels.save(str(path))
    with np.load(path) as opened:
        from_npz = GraspLabels.load(opened)
        from_dict = GraspLabels.load({k: opened[k] for k in opened.files})
    for back in (GraspLabels.load(path), GraspLabels.load(str(path)), from_npz, from_dict):
        assert back.meta == labels.meta
        for f in dataclasses.fields(GraspLabels):
            if f.name == "meta":
                continue
            a, b = getattr(labels, f.name), getattr(back, f.name)
            assert b.dtype == a.dtype, f.name
            np.testing.assert_array_equal(b, a, err_msg=f.name)  # NaN and inf kept too
    # optional arrays absent stay None; an array that is not a field is left out
    plain = {name: getattr(labels, name) for name in ARRAYS if name != "collides"}
    np.savez(tmp_path / "p.npz", **plain, meta=json.dumps(labels.meta), extra=np.zeros(3))
    back = GraspLabels.load(tmp_path / "p.npz")
    assert back.collides is None and back.sigma_min is None and not hasattr(back, "extra")


def _write(path, **changes):
    arrays = {name: getattr(_random_labels(), name) for name in ARRAYS}
    arrays["meta"] = np.array(json.dumps({"mu": 0.3, "width_max": 0.1}))
    arrays.update(changes)
    np.savez(path, **{k: v for k, v in arrays.items() if v is not None})
    return path


def test_files_that_are_not_labels_are_refused_in_one_line(tmp_path):
    (tmp_path / "text.npz").write_text("not an archive")
    np.save(tmp_path / "one.npy", np.zeros(3))
    (tmp_path / "folder").mkdir()
    cases = [(tmp_path / "none.npz", "no such label file"),
             (tmp_path / "text.npz", "not an .npz archive"),
             (tmp_path / "one.npy", "not an .npz archive"),
             (tmp_path / "folder", "not a label file"),
             (_write(tmp_path / "a.npz", center=None), "no 'center' array"),
             (_write(tmp_path / "b.npz", meta=None), "no 'meta' array"),
             (_write(tmp_path / "c.npz", points=np.zeros((7, 3))), "'points' has shape (7, 3)"),
             (_write(tmp_path / "d.npz", width=np.zeros(6)), "'width' has shape (6,)"),
             (_write(tmp_path / "e.npz", meta=np.array("{not json")), "'meta' is not"),
             (_write(tmp_path / "f.npz", meta=np.array("[1, 2]")), "'meta' is not"),
             (_write(tmp_path / "g.npz", code=np.full(7, 3)), "'code' codes must be 0, 1 or 2"),
             (_write(tmp_path / "h.npz", collides=np.zeros(7)), "'collides' is float64"),
             (_write(tmp_path / "i.npz", width=np.array(["a"] * 7)), "'width' is <U1")]
    for path, words in cases:
        with pytest.raises(InputError) as caught:
            GraspLabels.load(path)
        message = str(caught.value)
        assert "\n" not in message and words in message and path.name in message, message
    with pytest.raises(InputError, match="expected a label file's path"):
        GraspLabels.load(3)


def test_exports_take_a_label_file_or_its_arrays(tmp_path, duck):
    _, labels = duck
    path = str(tmp_path / "duck.npz")
    labels.save(path)
    expected = graspnet_array(labels)
    with np.load(path) as opened:  # today's AttributeError: np.load has no .meta
        np.testing.assert_array_equal(graspnet_array(opened), expected)
        save_graspnet(str(tmp_path / "g.npy"), opened)
    np.testing.assert_array_equal(graspnet_array(path), expected)
    np.testing.assert_array_equal(np.load(tmp_path / "g.npy"), expected)
    found = save_acronym(str(tmp_path / "a.h5"), path, DUCK)
    assert (found.file, found.scale) == (os.path.relpath(os.path.join(DATA, "duck_vhacd.obj"),
                                                         tmp_path), 0.05)


# -- graspnetAPI's loader -------------------------------------------------------------------

@pytest.mark.parametrize("per_pose_depth", [False, True])
def test_graspnetapi_reads_the_poses_and_scores(tmp_path, duck, graspnet_grasp, per_pose_depth):
    _, labels = duck
    n = len(labels)
    made = (with_meta_and_depth(labels, depths_reaching_past(labels, 0)) if per_pose_depth
            else labels)
    depth = saved_depth(made, 0.016)  # ParallelJaw(0.08): tips 0.2 w past the centre
    path = str(tmp_path / "duck.npy")
    save_graspnet(path, made)
    gg = graspnet_grasp.GraspGroup().from_npy(path)
    assert len(gg) == n
    np.testing.assert_allclose(gg.translations, labels.center, atol=1e-15)
    np.testing.assert_allclose(gg.widths, labels.width, atol=1e-15)
    np.testing.assert_allclose(gg.depths, depth)
    np.testing.assert_allclose(gg.heights, 0.016)  # fingers 0.2 w high
    R = gg.rotation_matrices
    np.testing.assert_allclose(R.transpose(0, 2, 1) @ R, np.broadcast_to(np.eye(3), R.shape),
                               atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
    np.testing.assert_allclose(R[:, :, 0], labels.approach_axis, atol=1e-12)
    # graspnetAPI's gripper frame: the fingers run along +x to their tips at x = depth, at
    # y = -width/2 and +width/2, height along z; the contacts must be on their inner faces
    T = np.zeros((n, 4, 4))
    T[:, :3, :3], T[:, :3, 3] = R, gg.translations
    for jaw, side in ((0, -1), (1, 1)):
        q = in_frame(T, labels.points[:, jaw])
        # on the pad's face, pressed in by at most the pads' compliance
        inward = side * (side * gg.widths / 2 - q[:, 1])
        press = labels.meta["hand"]["pad_compliance"]
        assert np.all((inward >= -1e-12) & (inward <= press + 1e-12))
        assert np.all(q[:, 0] <= gg.depths + 1e-12)  # not past the fingertips
        assert np.all(q[:, 0] >= gg.depths - 0.04 - 1e-12)  # on the 0.5 w finger
        assert np.all(np.abs(q[:, 2]) <= gg.heights / 2 + 1e-12)
    closed = labels.code == 2
    np.testing.assert_allclose(gg.scores[closed], 1.1 - labels.least_friction[closed])
    assert np.all(gg.scores[~closed] == -1)
    assert np.all(gg.object_ids == -1)
    first = gg[0]  # graspnetAPI's Grasp, too
    np.testing.assert_allclose(first.translation, gg.translations[0])


# -- ACRONYM's loading path -------------------------------------------------------------------

def check_same_solid(loaded, obj, size):
    """The loaded mesh bounds the object's solid: the object's surface lies on it, and it
    lies on or inside the object (a URDF's overlapping convex pieces have inner faces)."""
    ours = obj.to_trimesh()
    np.testing.assert_allclose(loaded.bounds, ours.bounds, atol=1e-12 * size)
    samples = trimesh.sample.sample_surface(ours, 300, seed=0)[0]
    assert surface_distance(loaded, np.vstack([samples, ours.vertices])).max() < 1e-9 * size
    depth = trimesh.proximity.signed_distance(ours, loaded.vertices)  # > 0 inside
    assert depth.min() > -1e-9 * size


@pytest.mark.parametrize("per_pose_depth", [False, True])
def test_acronym_loads_the_duck_and_puts_the_pandas_fingers_on_the_contacts(
        tmp_path, duck, per_pose_depth):
    obj, labels = duck
    n = len(labels)
    made = with_meta_and_depth(labels, depths_reaching_past(labels, 1) if per_pose_depth
                               else None, gripper="panda", tip_offset=PANDA_TIP)
    depth = saved_depth(made, 0.016)
    h5 = str(tmp_path / "duck.h5")
    found = save_acronym(h5, made, DUCK)
    assert found.reason is None and not (tmp_path / "duck.obj").exists()
    mesh, name, scale = acronym_load_mesh(h5, str(tmp_path))  # the default root: the .h5's
    assert isinstance(mesh, trimesh.Trimesh)
    assert scale == 0.05 and name == os.path.relpath(os.path.join(DATA, "duck_vhacd.obj"),
                                                     tmp_path)
    size = float(np.ptp(mesh.bounds, axis=0).max())
    assert surface_distance(mesh, labels.points.reshape(-1, 3)).max() < 1e-9 * size
    check_same_solid(mesh, obj, size)
    T, success = acronym_load_grasps(h5)
    assert T.shape == (n, 4, 4) and success.dtype == np.int64
    assert success.tolist() == (labels.code == 2).astype(int).tolist()  # not collision-checked
    np.testing.assert_allclose(T[:, 3], np.broadcast_to([0, 0, 0, 1.0], (n, 4)))
    np.testing.assert_allclose(np.linalg.det(T[:, :3, :3]), 1.0, atol=1e-12)
    assert np.all(labels.width / 2 <= PANDA_X)  # the Panda opens its fingers to x = ±0.041
    past = along_approach(labels)
    for jaw, side in ((0, -1), (1, 1)):
        q = in_frame(T, labels.points[:, jaw])  # in the Panda's frame: on its finger
        # on the pad's face, pressed in by at most the pads' compliance
        inward = side * labels.width / 2 - q[:, 0]
        press = labels.meta["hand"]["pad_compliance"]
        assert np.all((side * inward >= -1e-12) & (side * inward <= press + 1e-12))
        assert np.all(np.abs(q[:, 1]) <= 0.008 + 1e-12)  # within the 0.2 w high pad
        np.testing.assert_allclose(q[:, 2], PANDA_TIP - depth + past[:, jaw], atol=1e-12)
        # on the Panda's fingers, from z = 0.066 to their tips
        assert np.all((q[:, 2] >= PANDA_BASE) & (q[:, 2] <= PANDA_TIP + 1e-12)), q[:, 2]


def test_acronym_default_hand_frame_puts_our_fingers_on_the_contacts(tmp_path, duck):
    """Without a tip offset of its own the hand's base frame is our box hand's, the palm's
    back face: the contacts lie on the fingers' inner faces, between bases and tips."""
    _, labels = duck
    h5 = str(tmp_path / "d.h5")
    save_acronym(h5, labels, DUCK)
    T, _ = acronym_load_grasps(h5)
    w = 0.08
    finger_length, palm, height = 0.5 * w, 0.1 * w, 0.2 * w
    tip = finger_length + palm
    depth, past = saved_depth(labels, 0.2 * w), along_approach(labels)
    for jaw, side in ((0, -1), (1, 1)):
        q = in_frame(T, labels.points[:, jaw])
        # on the pad's face, pressed in by at most the pads' compliance
        inward = side * labels.width / 2 - q[:, 0]
        press = labels.meta["hand"]["pad_compliance"]
        assert np.all((side * inward >= -1e-12) & (side * inward <= press + 1e-12))
        assert np.all(np.abs(q[:, 1]) <= height / 2 + 1e-12)
        assert np.all((q[:, 2] >= tip - finger_length - 1e-12) & (q[:, 2] <= tip + 1e-12))
        np.testing.assert_allclose(q[:, 2], tip - depth + past[:, jaw], atol=1e-12)
    with h5py.File(h5, "r") as f:
        assert f["gripper/tip_offset"][()] == pytest.approx(tip)
        assert f["gripper/offset"][()] == pytest.approx(tip - 0.2 * w)


def _urdf(folder, name, body):
    path = folder / f"{name}.urdf"
    path.write_text(f'<robot name="{name}"><link name="l">{body}</link></robot>')
    return str(path)


def test_acronym_writes_the_surface_when_no_mesh_file_says_it(tmp_path):
    cube_obj = os.path.join(DATA, "cube.obj")
    mesh = f'<mesh filename="{cube_obj}" scale="{{}}"/>'
    collision = '<collision><origin xyz="{}" rpy="{}"/><geometry>{}</geometry></collision>'
    cases = {
        "placed": _urdf(tmp_path, "placed", collision.format("0.1 0 0", "0 0 0.3",
                                                             mesh.format("0.2 0.2 0.2"))),
        "uneven": _urdf(tmp_path, "uneven", collision.format("0 0 0", "0 0 0",
                                                             mesh.format("0.2 0.1 0.3"))),
        "pieces": _urdf(tmp_path, "pieces",
                        collision.format("0 0 0", "0 0 0", '<box size="0.2 0.1 0.1"/>')
                        + collision.format("0.2 0 0", "0 0 0", '<box size="0.1 0.1 0.1"/>')),
        "cube": "cube",
        "box": trimesh.creation.box([0.3, 0.2, 0.1]),
    }
    roots = tmp_path / "out"
    roots.mkdir()
    for key, source in cases.items():
        obj = load_object(source, allow_outside_meshes=True)
        labels = grasp_labels(obj, ParallelJaw(3.0 if key == "cube" else 0.4), mu=0.5,
                              count=4, collision=False, least_friction=False, epsilon=False)
        h5 = str(roots / f"{key}.h5")
        found = save_acronym(h5, labels, source, mesh_root=str(tmp_path),
                             allow_outside_meshes=True)
        assert found.reason and found.file == f"out/{key}.obj", (key, found)
        loaded, _, scale = acronym_load_mesh(h5, str(tmp_path))
        assert scale == 1.0
        size = float(np.ptp(obj.bounds, axis=0).max())
        check_same_solid(loaded, obj, size)
        assert surface_distance(loaded, labels.points.reshape(-1, 3)).max() < 1e-9 * size


# -- forceclosure export ------------------------------------------------------------------------

def test_export_command_on_a_grasps_file(tmp_path, capsys):
    labels = str(tmp_path / "duck.npz")
    assert main(["grasps", DUCK, "--width", "0.08", "--count", "12", "--mu", "0.5",
                 "--no-collision", "--out", labels, "--json"]) == 0
    capsys.readouterr()
    g, a = tmp_path / "g.npy", tmp_path / "a.h5"
    assert main(["export", labels, "--graspnet", str(g), "--acronym", str(a), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)["exported"][0]
    assert summary["acronym"]["scale"] == 0.05 and summary["acronym"]["note"] is None
    saved = GraspLabels.load(labels)
    np.testing.assert_array_equal(np.load(g), graspnet_array(saved))
    mesh, _, _ = acronym_load_mesh(str(a), str(tmp_path))
    assert surface_distance(mesh, saved.points.reshape(-1, 3)).max() < 1e-9
    # another mesh root, and the object named by hand
    assert main(["export", labels, "--acronym", str(a), "--mesh-root", DATA,
                 "--object", DUCK]) == 0
    assert acronym_load_mesh(str(a), DATA)[1] == "duck_vhacd.obj"
    assert "scale 0.05" in capsys.readouterr().out


def test_export_command_refuses_bad_input_before_writing(tmp_path, capsys):
    labels = tmp_path / "l.npz"
    grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=3, collision=False).save(str(labels))
    (tmp_path / "job").mkdir()
    out = tmp_path / "o.npy"
    cases = [([], "nothing to write"),
             (["--graspnet", str(tmp_path / "o.h5")], "written as .npy"),
             (["--acronym", str(tmp_path / "o.npy")], "written as .h5 or .hdf5"),
             (["--graspnet", str(tmp_path / "no" / "o.npy")], "does not exist"),
             (["--graspnet", str(out), "--mesh-root", str(tmp_path / "no")], "not a folder"),
             (["--graspnet", str(out), "--object", "nowhere.stl"], "no such file"),
             (["--graspnet", str(out), "--part", "l"], "go with --object"),
             (["--graspnet", str(labels)], "written as .npy"),
             (["--graspnet", str(out), "--acronym", str(out)], "its own file"),
             (["--graspnet", str(out), "--acronym", str(tmp_path / "a.h5"), "--object",
               "cube", "--graspnet-score", "friction"], None)]
    for extra, words in cases:
        status = main(["export", str(labels), *extra])
        err = capsys.readouterr().err
        if words is None:  # the good one, last: written
            assert status == 0 and out.exists()
            continue
        assert status == 2 and err.count("\n") == 1 and words in err, (extra, err)
        assert not out.exists()
    for labels_arg, words in ((str(tmp_path / "none.npz"), "no such label file"),
                              (str(tmp_path / "job"), "not the output of 'dataset --gripper")):
        assert main(["export", labels_arg, "--graspnet", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and words in err, err
    no_meta = tmp_path / "n.npz"  # labels whose meta locates no object
    loaded = GraspLabels.load(labels)
    dataclasses.replace(loaded, meta={**loaded.meta, "object": "lost"}).save(str(no_meta))
    assert main(["export", str(no_meta), "--acronym", str(tmp_path / "n.h5")]) == 2
    assert "--object FILE" in capsys.readouterr().err
    assert not (tmp_path / "n.h5").exists()


def _sha256(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_export_command_on_a_dataset_folder(tmp_path, capsys, duck):
    """A folder laid out as 'dataset --gripper' writes it (job.json, objects/<stem>.json
    records naming their .npz and its SHA-256; the long test runs the real command)."""
    _, labels = duck
    folder = tmp_path / "ds"
    (folder / "objects").mkdir(parents=True)
    (folder / "job.json").write_text(json.dumps({"mode": "gripper", "allow_open": False,
                                                 "allow_outside_meshes": False}))
    cube = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=3, collision=False)
    records = {"duck": (DUCK, labels), "cube": ("cube", cube), "changed": ("cube", cube)}
    for stem, (path, made) in records.items():
        made.save(str(folder / "objects" / f"{stem}.npz"))
        record = {"path": path, "status": "done", "labels_file": f"{stem}.npz",
                  "labels_sha256": _sha256(folder / "objects" / f"{stem}.npz")}
        (folder / "objects" / f"{stem}.json").write_text(json.dumps(record))
    (folder / "objects" / "changed.npz").write_bytes(b"changed since")
    (folder / "objects" / "failed.json").write_text(json.dumps({"path": "x.stl",
                                                                "status": "failed"}))
    g, a = tmp_path / "g", tmp_path / "a"
    assert main(["export", str(folder), "--graspnet", str(g), "--acronym", str(a)]) == 2
    captured = capsys.readouterr()
    assert "its labels file 'changed.npz' changed since its record was written" in captured.err
    assert "1 records not done" in captured.out
    assert sorted(os.listdir(g)) == ["cube.npy", "duck.npy"]
    assert sorted(os.listdir(a)) == ["cube.h5", "cube.obj", "duck.h5"]
    np.testing.assert_array_equal(np.load(g / "duck.npy"), graspnet_array(labels))
    mesh, _, scale = acronym_load_mesh(str(a / "duck.h5"), str(a))
    assert scale == 0.05
    assert surface_distance(mesh, labels.points.reshape(-1, 3)).max() < 1e-9
    cube_mesh, name, _ = acronym_load_mesh(str(a / "cube.h5"), str(a))
    assert name == "cube.obj" and cube_mesh.is_watertight
    assert cube_mesh.volume == pytest.approx(8.0, rel=1e-12)
    for bad, words in (([str(folder), "--graspnet", str(folder)], "the dataset's own folder"),
                       ([str(folder), "--graspnet", str(g / "duck.npy")], "this is a file"),
                       ([str(folder), "--graspnet", str(g), "--object", "cube"],
                        "names one object")):
        assert main(["export", *bad]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and words in err, err


@pytest.mark.long
def test_export_of_a_real_gripper_dataset(tmp_path, capsys):
    """'dataset --gripper parallel-jaw' on the duck and a box URDF, then export: ACRONYM's
    loading path reads each object back on its contacts."""
    out = tmp_path / "ds"
    cube_small = os.path.join(DATA, "cube_small.urdf")
    assert main(["dataset", DUCK, cube_small, "--gripper", "parallel-jaw", "--width", "0.08",
                 "--mu", "0.5", "--count", "10", "--workers", "1", "--out", str(out)]) == 0
    a = tmp_path / "a"
    assert main(["export", str(out), "--acronym", str(a), "--graspnet", str(a)]) == 0
    h5s = sorted(p for p in os.listdir(a) if p.endswith(".h5"))
    assert len(h5s) == 2 and len([p for p in os.listdir(a) if p.endswith(".npy")]) == 2
    for h5 in h5s:
        labels = GraspLabels.load(out / "objects" / (h5[:-3] + ".npz"))
        mesh, _, scale = acronym_load_mesh(str(a / h5), str(a))
        assert scale == (0.05 if h5.startswith("duck") else 1.0)
        assert surface_distance(mesh, labels.points.reshape(-1, 3)).max() < 1e-9
