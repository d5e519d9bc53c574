"""A hand's URDF whose meshes lie outside its folder: refused by default, read with
``--allow-outside-meshes`` (the flag its refusal names), in ``grasps`` and ``dataset``.

The hand is pybullet_data's panda.urdf, unchanged but for its mesh paths: copied into
``hand/urdf/`` naming ``../meshes/...``, its collision meshes copied to ``hand/meshes/``.
Read that way it must be the very hand of the file where pybullet_data ships it.
"""

import json
import shutil
from pathlib import Path

import pybullet_data
import pytest

from forceclosure.app.cli import main
from forceclosure.datasets import GripperJob, run_dataset
from forceclosure.errors import InputError
from forceclosure.gripper.grippers import make_gripper

DATA = Path(pybullet_data.getDataPath())
PANDA = DATA / "franka_panda" / "panda.urdf"
CUBE = DATA / "cube_small.urdf"  # 5 cm: within the panda's 8 cm


@pytest.fixture
def urdf(tmp_path):
    shutil.copytree(DATA / "franka_panda" / "meshes" / "collision",
                    tmp_path / "hand" / "meshes" / "collision")
    (tmp_path / "hand" / "urdf").mkdir()
    text = PANDA.read_text().replace("package://meshes/", "../meshes/")
    assert "../meshes/collision/hand.obj" in text
    path = tmp_path / "hand" / "urdf" / "panda.urdf"
    path.write_text(text)
    return path


def test_make_gripper(urdf):
    with pytest.raises(InputError, match="outside") as refusal:
        make_gripper(str(urdf))
    assert "--allow-outside-meshes" in str(refusal.value)
    hand = make_gripper(str(urdf), allow_outside_meshes=True)
    assert hand.shape() == make_gripper(str(PANDA)).shape()


def test_dataset_job(urdf, tmp_path):
    with pytest.raises(InputError, match="outside"):
        GripperJob(width=None, mu=0.5, count=2, hand=str(urdf))
    job = GripperJob(width=None, mu=0.5, count=2, hand=str(urdf), allow_outside_meshes=True)
    assert job.identity()["hand"] == make_gripper(str(PANDA)).shape()
    summary = run_dataset([str(CUBE)], tmp_path / "out", job, workers=1, progress=False)
    assert (summary.done, summary.failed) == (1, 0)


def test_cli(urdf, tmp_path, capsys):
    argv = ["grasps", str(CUBE), "--gripper", str(urdf), "--mu", "0.5", "--count", "2",
            "--out", str(tmp_path / "labels.npz")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "outside" in err and "--allow-outside-meshes" in err and err.count("\n") == 1
    assert main([*argv, "--allow-outside-meshes"]) == 0, capsys.readouterr().err
    out = tmp_path / "out"
    argv = ["dataset", str(CUBE), "--out", str(out), "--gripper", str(urdf), "--mu", "0.5",
            "--count", "2", "--workers", "1", "--allow-outside-meshes"]
    assert main(argv) == 0, capsys.readouterr().err


def test_a_relative_hand_file_is_stored_absolute(urdf, tmp_path, monkeypatch, capsys):
    """``--gripper panda.urdf`` typed in the hand's folder: job.json names the file by its
    absolute path (workers elsewhere find it), so the same hand spelt absolute resumes."""
    out = tmp_path / "out"
    common = ["--out", str(out), "--mu", "0.5", "--count", "2", "--workers", "1",
              "--allow-outside-meshes"]
    monkeypatch.chdir(urdf.parent)
    assert main(["dataset", str(CUBE), "--gripper", urdf.name, *common]) == 0
    capsys.readouterr()
    job = GripperJob(width=None, mu=0.5, count=2, hand=urdf.name, allow_outside_meshes=True)
    assert job.hand == str(urdf)
    monkeypatch.chdir(tmp_path)
    assert json.loads((out / "job.json").read_text())["gripper"] == str(urdf)
    assert main(["dataset", str(CUBE), "--gripper", str(urdf), *common]) == 0
    assert "1 skipped" in capsys.readouterr().out
