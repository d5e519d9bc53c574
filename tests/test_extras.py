"""The optional parts (``forceclosure.extras``): with the package of an extra made
unimportable (``sys.modules[name] = None``, as if not installed), the command that needs it
stops before any work with one line naming the extra to install, exit status 2; the core
commands do not need them."""

import sys
import tomllib
from pathlib import Path

import pytest

from forceclosure.app.cli import main
from forceclosure.extras import EXTRAS, MissingExtra, require

ROOT = Path(__file__).resolve().parents[1]


def _missing(monkeypatch, *modules: str) -> None:
    """Make ``modules`` unimportable, and forget the package's modules that imported them."""
    for name in modules:
        monkeypatch.setitem(sys.modules, name, None)
    for name in ("forceclosure.pictures.view",):
        monkeypatch.delitem(sys.modules, name, raising=False)


def _one_line(capsys, extra: str) -> str:
    captured = capsys.readouterr()
    err = captured.err
    assert err.count("\n") == 1, err
    assert f"pip install 'forceclosure[{extra}]'" in err and "Traceback" not in err
    return err


def test_the_extras_are_the_ones_pyproject_declares_and_test_installs_them_all():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    extras = project["optional-dependencies"]
    core = " ".join(project["dependencies"])
    for extra, package in EXTRAS.items():
        assert any(d.startswith(package) for d in extras[extra]), extra
        assert any(d.startswith(package) for d in extras["test"]), package
        assert package not in core, f"{package} is a core dependency"


def test_require_names_the_extra(monkeypatch):
    _missing(monkeypatch, "pyarrow", "pyarrow.parquet")  # either may be imported already
    with pytest.raises(MissingExtra) as e:
        require("pyarrow.parquet", "the dataset's table", "table")
    assert str(e.value) == ("the dataset's table needs pyarrow: install forceclosure's 'table' "
                            "extra (pip install 'forceclosure[table]')")
    assert isinstance(e.value, ImportError)


def test_the_dataset_without_pyarrow_names_the_table_extra(tmp_path, monkeypatch, capsys):
    _missing(monkeypatch, "pyarrow", "pyarrow.parquet")
    out = tmp_path / "out"
    assert main(["dataset", "square", "--out", str(out), "--contact", "soft", "--mu", "0.5",
                 "--workers", "1"]) == 2
    assert "the dataset's table needs pyarrow" in _one_line(capsys, "table")
    assert not (out / "objects").exists()  # refused before any work


def test_the_html_view_without_plotly_names_the_view_extra(tmp_path, monkeypatch, capsys):
    _missing(monkeypatch, "plotly", "plotly.graph_objects")
    page = tmp_path / "v.html"
    assert main(["synthesize", "square", "--mu", "0.5", "--html", str(page)]) == 2
    assert "the interactive HTML view needs plotly" in _one_line(capsys, "view")
    assert not page.exists()
    # the library's own door says the same
    with pytest.raises(MissingExtra, match=r"pip install 'forceclosure\[view\]'"):
        import forceclosure.pictures.view  # noqa: F401


def test_grasps_and_gripper_datasets_check_plotly_before_any_work(tmp_path, monkeypatch,
                                                                   capsys):
    """``grasps --html`` and ``dataset --gripper --html`` refuse up front, as synthesize: no
    grasp is labelled, no file or folder written."""
    import forceclosure.gripper.labels as labels

    calls = []
    real = labels.grasp_labels
    monkeypatch.setattr(labels, "grasp_labels", lambda *a, **k: calls.append(1) or real(*a, **k))
    _missing(monkeypatch, "plotly", "plotly.graph_objects")
    page = tmp_path / "v.html"
    assert main(["grasps", "cube", "--width", "3", "--mu", "0.5", "--count", "2",
                 "--html", str(page)]) == 2
    assert "the interactive HTML view needs plotly" in _one_line(capsys, "view")
    out, pages = tmp_path / "out", tmp_path / "pages"
    assert main(["dataset", "cube", "--out", str(out), "--gripper", "parallel-jaw", "--width",
                 "3", "--mu", "0.5", "--count", "2", "--workers", "1", "--html",
                 str(pages)]) == 2
    assert "the interactive HTML view needs plotly" in _one_line(capsys, "view")
    assert calls == [] and not page.exists() and not out.exists() and not pages.exists()


def test_a_dask_cluster_without_distributed_names_the_dask_extra(tmp_path, monkeypatch, capsys):
    _missing(monkeypatch, "distributed")
    assert main(["dataset", "square", "--out", str(tmp_path / "out"),
                 "--scheduler", "tcp://127.0.0.1:1"]) == 2
    assert "--scheduler (a Dask cluster) needs distributed" in _one_line(capsys, "dask")


def test_the_acronym_export_without_h5py_names_the_export_extra(monkeypatch):
    from forceclosure.io.export import require_h5py

    _missing(monkeypatch, "h5py")
    with pytest.raises(MissingExtra, match=r"ACRONYM export needs h5py.*forceclosure\[export\]"):
        require_h5py()


def test_the_core_runs_without_the_extras(monkeypatch, capsys):
    """Analysis, synthesis and the PNG picture with none of the optional packages."""
    _missing(monkeypatch, *EXTRAS.values(), "pyarrow.parquet", "plotly.graph_objects")
    assert main(["demo"]) == 0
    assert "closure" in capsys.readouterr().out
