"""``dataset --gripper`` takes ``grasps``'s options (issue 24): recorded in job.json,
honoured on every object, refused without --gripper or when a resumed run changes them.

"Honoured" is checked against the library called directly with the same options and the
seed the dataset documents for each object (object_seed of the job's seed and the object's
fingerprint): the dataset's saved labels must be exactly those.
"""

import json
import re
from pathlib import Path

import numpy as np
import pytest

from forceclosure.app.cli import main
from forceclosure.datasets import GripperJob, fingerprint, record_name, run_dataset
from forceclosure.datasets.gripper_job import object_seed
from forceclosure.errors import InputError
from forceclosure.gripper.jaw import ParallelJaw
from forceclosure.gripper.labels import GraspLabels, grasp_labels
from forceclosure.gripper.robust import robust_labels
from forceclosure.gripper.support import support_plane

OBJECTS = ("cube", "hexagonal-prism")
OPTIONS = ["--approaches", "2", "--depths", "1", "--tilt", "0.3", "--clearance", "0.05",
           "--no-epsilon", "--robust", "--robust-samples", "3", "--metrics", "--support-plane"]
BASE = ["--gripper", "parallel-jaw", "--width", "3", "--mu", "0.5", "--count", "6",
        "--workers", "1"]


def _labels(out: Path, name: str) -> GraspLabels:
    return GraspLabels.load(str(out / "objects" / record_name(Path(name)).replace(".json",
                                                                                  ".npz")))


def test_options_are_recorded_and_honoured(tmp_path, capsys):
    import plotly.offline

    out, exports = tmp_path / "out", tmp_path / "gn"
    pictures, pages = tmp_path / "pictures", tmp_path / "pages"
    argv = ["dataset", *OBJECTS, "--out", str(out), *BASE, *OPTIONS,
            "--export", "graspnet", str(exports), "--plot", str(pictures), "--plot-top", "2",
            "--html", str(pages)]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "export graspnet: 2 files" in err and "export plot: 2 files" in err
    job = json.loads((out / "job.json").read_text())
    assert (job["approaches"], job["depths"], job["tilt"], job["clearance"]) == (2, 1, 0.3, 0.05)
    assert job["epsilon"] is False and job["metrics"] is True and job["collision"] is True
    assert job["support_plane"] is True
    assert job["robust"]["samples"] == 3 and job["robust"]["pose_sigma"] == 0.03  # 1 % of 3
    assert job["exports"] == [["graspnet", str(exports)]]
    assert (job["plot"], job["plot_top"], job["html"]) == (str(pictures), 2, str(pages))
    stamp_job = GripperJob(width=3.0, mu=0.5, count=6)  # the fingerprint does not depend on them
    for name in OBJECTS:
        saved = _labels(out, name)
        seed = object_seed(0, fingerprint(name, stamp_job))
        direct = grasp_labels(name, ParallelJaw(3.0), 0.5, 6, seed, approaches=2, depths=1,
                              tilt=0.3, clearance=0.05, epsilon=False,
                              support=support_plane(name))
        for key in ("center", "closing_axis", "approach_axis", "width", "points", "code",
                    "least_friction"):
            assert np.array_equal(getattr(saved, key), getattr(direct, key)), (name, key)
        assert np.all(np.isnan(saved.epsilon))
        assert saved.meta["approaches"] == 2 and saved.meta["tilt"] == 0.3
        assert saved.meta["collision"]["clearance"] == 0.05
        assert saved.meta["support_plane"] == support_plane(name).to_dict()
        rob = robust_labels(name, direct, ParallelJaw(3.0), 0.5, samples=3, seed=seed,
                            pose_sigma=0.03)
        assert np.array_equal(saved.robust_probability, rob.probability), name
        assert saved.sigma_min.shape == (6,) and np.all(saved.sigma_min >= 0)
        npy = np.load(exports / (Path(record_name(Path(name))).stem + ".npy"))
        assert npy.shape == (6, 17)
        assert np.allclose(npy[:, 1], saved.width)  # GraspNet's column 1: the width
        png = pictures / (Path(record_name(Path(name))).stem + ".png")
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the pages: one per object, each under 1 MB, all loading the one plotly.min.js beside
    # them, the installed plotly's
    stems = sorted(Path(record_name(Path(name))).stem for name in OBJECTS)
    assert sorted(p.name for p in pages.iterdir()) == [*(s + ".html" for s in stems),
                                                       "plotly.min.js"]
    for stem in stems:
        page = (pages / (stem + ".html")).read_text(encoding="utf-8")
        assert len(page.encode("utf-8")) < 1_000_000
        assert re.findall(r"<script src=\"([^\"]*)\"", page) == ["plotly.min.js"]
        assert "fc-plotly" not in page  # nothing of plotly.js inlined
    shared = pages / "plotly.min.js"
    assert shared.read_text(encoding="utf-8") == plotly.offline.get_plotlyjs()
    # a resumed run must ask for the same options: another tilt is another job
    other = [("0" if a == "0.3" else a) for a in argv]  # --tilt 0
    assert other != argv and main(other) == 2
    assert "tilt 0.3 there, 0.0 here" in capsys.readouterr().err
    shared.unlink()  # the pages kept from the run before need it: written again
    assert main(argv) == 0  # the same options: resumed, nothing redone
    assert "2 skipped" in capsys.readouterr().out
    assert shared.read_text(encoding="utf-8") == plotly.offline.get_plotlyjs()


def test_a_job_file_from_before_the_options_still_resumes(tmp_path):
    out = tmp_path / "out"
    job = GripperJob(width=3.0, mu=0.5, count=4)
    assert run_dataset(["cube"], out, job, workers=1, progress=False).computed == 1
    held = json.loads((out / "job.json").read_text())
    for key in GripperJob.IDENTITY_DEFAULTS:
        del held[key]
    (out / "job.json").write_text(json.dumps(held))
    records = list((out / "objects").glob("*.json"))  # an old folder's records lack them too
    assert len(records) == 1
    for file in records:
        record = json.loads(file.read_text())
        for key in GripperJob.IDENTITY_DEFAULTS:
            del record["job"][key]
        file.write_text(json.dumps(record))
    again = run_dataset(["cube"], out, job, workers=1, progress=False)
    assert (again.skipped, again.computed) == (1, 0)
    with pytest.raises(InputError, match=r"tilt 0\.0 there, 0\.5 here"):
        run_dataset(["cube"], out, GripperJob(width=3.0, mu=0.5, count=4, tilt=0.5),
                    workers=1, progress=False)


@pytest.mark.parametrize("argv, message", [
    (["--tilt", "0.3"], "--tilt is for --gripper"),
    (["--robust"], "--robust is for --gripper"),
    (["--export", "graspnet", "g"], "--export is for --gripper"),
    (["--plot", "p"], "--plot is for --gripper"),
    (["--support-plane"], "--support-plane is for --gripper"),
    ([*BASE, "--support-plane", "--no-collision"], "--support-plane is part of the collision"),
    ([*BASE, "--plot-top", "-1", "--plot", "p"], "--plot-top must be a whole number >= 0"),
    ([*BASE, "--no-collision", "--approaches", "2"], "--approaches is searched by the "
                                                      "collision check"),
    ([*BASE, "--tilt", "2"], "--tilt must be a share from 0 to 1"),
    ([*BASE, "--robust-samples", "5"], "--robust-samples needs --robust"),
    ([*BASE, "--no-epsilon", "--graspnet-score", "epsilon"], "needs the epsilon"),
    ([*BASE, "--export", "stl", "x"], "--export: unknown kind 'stl'"),
    ([*BASE, "--plot", ""], "--plot is empty: give a folder name"),
    ([*BASE, "--html", " "], "--html is empty: give a folder name"),
    ([*BASE, "--export", "graspnet", ""], "--export graspnet is empty: give a folder name"),
    ([*BASE, "--plot", "-"], "--plot -: results are not written to standard output"),
])
def test_refusals(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)  # a relative folder accepted by mistake lands here
    out = tmp_path / "out"
    assert main(["dataset", "cube", "--out", str(out), *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_exports_stay_out_of_the_dataset_folder(tmp_path, capsys):
    out = tmp_path / "out"
    for flags in (["--export", "graspnet", str(out)], ["--plot", str(out / "objects")]):
        assert main(["dataset", "cube", "--out", str(out), *BASE, *flags]) == 2
        assert "the dataset's own folder" in capsys.readouterr().err
    assert not out.exists()


def test_output_options_are_not_another_job(tmp_path, capsys):
    """Pictures and exports are redrawn each run: adding --plot, or changing the GraspNet
    score, resumes the finished dataset (nothing labelled again), and the files written
    follow the new options (not kept from the run before: a fresh dataset's are equal)."""
    out, gn, pictures = tmp_path / "out", tmp_path / "gn", tmp_path / "pictures"
    argv = ["dataset", "cube", "--out", str(out), *BASE, "--export", "graspnet", str(gn)]
    assert main(argv) == 0
    first = np.load(next(gn.glob("*.npy")))
    capsys.readouterr()
    assert main([*argv, "--plot", str(pictures), "--graspnet-score", "epsilon"]) == 0
    captured = capsys.readouterr()
    assert "1 skipped" in captured.out and "another job" not in captured.err, captured.err
    assert len(list(pictures.glob("*.png"))) == 1
    job = json.loads((out / "job.json").read_text())  # this run's outputs are recorded
    assert (job["plot"], job["graspnet_score"]) == (str(pictures), "epsilon")
    again = np.load(next(gn.glob("*.npy")))
    fresh_gn = tmp_path / "fresh-gn"
    assert main(["dataset", "cube", "--out", str(tmp_path / "fresh"), *BASE, "--export",
                 "graspnet", str(fresh_gn), "--graspnet-score", "epsilon"]) == 0
    fresh = np.load(next(fresh_gn.glob("*.npy")))
    assert np.array_equal(again, fresh) and not np.array_equal(again, first)


def test_the_hands_sizes_are_part_of_the_job(tmp_path, monkeypatch):
    """A dataset labelled with the panda's former sizes (palm 0.2044 wide, before 0.208) is
    another job for today's panda: refused as such, and its records (job.json removed) are
    computed again, so no dataset mixes the labels of two hand geometries."""
    import os
    from dataclasses import replace

    import pybullet_data

    from forceclosure.gripper.grippers import GRIPPERS

    cube = os.path.join(pybullet_data.getDataPath(), "cube_small.urdf")  # 5 cm
    out = tmp_path / "out"
    job = GripperJob(width=None, hand="panda", mu=0.5, count=3)
    assert GRIPPERS["panda"].palm_width == 0.208
    monkeypatch.setitem(GRIPPERS, "panda", replace(GRIPPERS["panda"], palm_width=0.2044))
    assert run_dataset([cube], out, job, workers=1, progress=False).computed == 1
    monkeypatch.undo()
    with pytest.raises(InputError, match=r"hand palm_width 0\.2044 there, 0\.208 here"):
        run_dataset([cube], out, job, workers=1, progress=False)
    (out / "job.json").unlink()
    again = run_dataset([cube], out, job, workers=1, progress=False)
    assert (again.computed, again.skipped) == (1, 0)
    assert json.loads((out / "job.json").read_text())["hand"]["palm_width"] == 0.208


@pytest.mark.parametrize("options, flag", [({"plot": ""}, "--plot"), ({"html": " "}, "--html"),
                                           ({"exports": [("graspnet", "")]},
                                            "--export graspnet")])
def test_the_library_refuses_an_empty_folder_too(options, flag):
    with pytest.raises(InputError, match=f"^{flag} is empty: give a folder name$"):
        GripperJob(width=3.0, mu=0.5, **options)


def test_exports_are_written_kind_by_kind(tmp_path):
    """``dataset --export`` writes each (kind, folder) on its own: a kind that cannot be
    written for an object (ACRONYM, its object's file gone) leaves the GraspNet files
    written; the same kind twice fills both folders; a file at least as new as its labels
    is kept unless asked otherwise, and a changed labels file is never exported."""
    from forceclosure.datasets.gripper_job import (
        export_dataset,
        labels_problem,
        sha256_of,
        write_exports,
    )
    from forceclosure.io.export import graspnet_array

    folder = tmp_path / "ds"
    (folder / "objects").mkdir(parents=True)
    (folder / "job.json").write_text(json.dumps({"mode": "gripper", "allow_open": False,
                                                 "allow_outside_meshes": False}))
    labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=4, collision=False)
    labels.save(str(folder / "objects" / "cube.npz"))
    record = {"path": str(tmp_path / "gone.stl"), "name": "cube", "status": "done",
              "labels_file": "cube.npz", "labels_sha256": sha256_of(folder / "objects" /
                                                                    "cube.npz")}
    a, b, h = tmp_path / "a", tmp_path / "b", tmp_path / "h"
    exports = [("graspnet", str(a)), ("acronym", str(h)), ("graspnet", str(b))]
    report = write_exports(folder, [record], exports)
    assert report["files"] == {"graspnet": 2, "acronym": 0}
    assert len(report["errors"]) == 1 and report["errors"][0].startswith("acronym cube.h5: ")
    for target in (a, b):
        np.testing.assert_array_equal(np.load(target / "cube.npy"), graspnet_array(labels))
    assert json.loads((folder / "exports.json").read_text()) == report
    # kept: a file newer than its labels is not written again (unless keep=False)
    (a / "cube.npy").write_bytes(b"kept")
    write_exports(folder, [record], exports[:1], keep=True)
    assert (a / "cube.npy").read_bytes() == b"kept"
    write_exports(folder, [record], exports[:1], keep=False)
    np.testing.assert_array_equal(np.load(a / "cube.npy"), graspnet_array(labels))
    # a labels file changed behind its record's back (the run's own check finds it when it
    # loads the records; the export, as 'forceclosure export DIR' runs it, hashes it again)
    (folder / "objects" / "cube.npz").write_bytes(b"changed")
    (b / "cube.npy").unlink()
    assert labels_problem(folder / "objects", record) == (
        "its labels file 'cube.npz' changed since its record was written")
    entries, errors = export_dataset(folder, [record], graspnet=b)
    assert entries == [] and not (b / "cube.npy").exists()
    assert "changed since its record was written" in errors[0][1]
