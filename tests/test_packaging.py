"""What an installed forceclosure carries besides code: its licence, its type marker and the
JSON schemas (found with :mod:`importlib.resources`, so in a wheel as in a checkout)."""

import json
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import jsonschema
import pytest

from forceclosure.errors import InputError
from forceclosure.schemas import SCHEMAS, load_schema

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "forceclosure"


def test_the_licence_file_is_the_one_pyproject_names():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["license"] == "MIT"
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License") and "the forceclosure developers" in text


def test_the_package_declares_its_type_hints():
    assert (PACKAGE / "py.typed").is_file()


def test_every_shipped_schema_is_a_valid_schema_that_the_package_finds():
    files = sorted(p.name for p in (PACKAGE / "schemas").glob("*.schema.json"))
    assert files == sorted(f"{name}.schema.json" for name in SCHEMAS)
    for name in SCHEMAS:
        schema = load_schema(name)
        jsonschema.Draft202012Validator.check_schema(schema)
        assert schema["$schema"].endswith("/draft/2020-12/schema")
    # the grasp file schema accepts the bundled examples the demo reads
    for example in ("planar.json", "spatial.json"):
        jsonschema.validate(json.loads((PACKAGE / "examples" / example).read_text()),
                            load_schema("grasp-file"))


def test_an_unknown_schema_name_is_refused_naming_the_schemas():
    with pytest.raises(InputError, match="no schema named 'grasp'; the schemas are grasp-file"):
        load_schema("grasp")


@pytest.mark.long
@pytest.mark.skipif(shutil.which("uv") is None, reason="builds the wheel with uv")
def test_the_wheel_carries_licence_type_marker_and_schemas(tmp_path):
    """Build the wheel as a user's installer would and read what is in it; then load the
    schemas from that wheel alone (on ``sys.path`` as a zip, no checkout)."""
    subprocess.run(["uv", "build", "--wheel", "--out-dir", str(tmp_path), str(ROOT)],
                   check=True, capture_output=True)
    (wheel,) = tmp_path.glob("forceclosure-*.whl")
    archive = zipfile.ZipFile(wheel)
    names = set(archive.namelist())
    assert "forceclosure/py.typed" in names
    assert {f"forceclosure/schemas/{n}.schema.json" for n in SCHEMAS} <= names
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names), sorted(names)
    # a plain install brings no optional package: each comes with its extra only
    (metadata,) = [n for n in names if n.endswith(".dist-info/METADATA")]
    requires = [line.split(":", 1)[1].strip() for line in
                archive.read(metadata).decode().splitlines() if line.startswith("Requires-Dist:")]
    for package, extra in (("pyarrow", "table"), ("plotly", "view"), ("distributed", "dask")):
        mine = [r for r in requires if r.startswith(package)]
        assert mine and all("extra ==" in r for r in mine), requires
        assert any(f"extra == '{extra}'" in r or f'extra == "{extra}"' in r for r in mine)
    code = ("import sys; sys.path.insert(0, sys.argv[1]); import forceclosure.schemas as s; "
            "assert s.__file__.startswith(sys.argv[1]), s.__file__; "
            "print(s.load_schema('regions')['title'])")
    out = subprocess.run([sys.executable, "-I", "-c", code, str(wheel)], check=True,
                         capture_output=True, text=True).stdout
    assert out.strip() == "forceclosure region set"
