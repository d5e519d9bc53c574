"""The package's layering (docs: DESIGN §5, issue 16): no import cycles, layers that import
nothing above them (geometry → contacts → analysis → synthesis/gripper → io → pictures →
datasets → app), and a declared public surface (``__all__``) in every public module.

The import graph is read from the source with :mod:`ast`, counting every ``import`` and
``from ... import`` wherever it stands (module level, inside functions, under
``TYPE_CHECKING``): a function-level import hides a cycle from the interpreter at import time,
not from the reader. The checker is first run on small packages written here whose cycles are
known, so that a checker which sees nothing cannot pass.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "forceclosure"


def module_files(root: Path, package: str) -> dict[str, Path]:
    """Every module of ``package`` under ``root``, by dotted name."""
    found = {}
    for path in sorted((root / package).rglob("*.py")):
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return found


def import_graph(root: Path, package: str) -> dict[str, dict[str, list[int]]]:
    """``{module: {imported module of the package: [line, ...]}}``.

    ``from a import b`` counts as importing ``a.b`` when that is a module, else ``a`` (whose
    ``__init__`` defines ``b``).
    """
    modules = module_files(root, package)

    def owner(name: str) -> str | None:
        while name and name not in modules:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, dict[str, list[int]]] = {}
    for name, path in modules.items():
        here = name if path.name == "__init__.py" else name.rpartition(".")[0]
        edges: dict[str, list[int]] = {}
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = here.split(".")
                    base = base[: len(base) - (node.level - 1)]
                    start = ".".join(base + ([node.module] if node.module else []))
                else:
                    start = node.module or ""
                targets = [f"{start}.{a.name}" if f"{start}.{a.name}" in modules else start
                           for a in node.names]
            for target in targets:
                if target == package or target.startswith(package + "."):
                    found = owner(target)
                    if found is not None and found != name:
                        edges.setdefault(found, []).append(node.lineno)
        graph[name] = edges
    return graph


def cycles(graph: dict[str, dict[str, list[int]]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            for w in children:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    component = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        component.append(w)
                        if w == v:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return found


def describe(graph: dict[str, dict[str, list[int]]], component: list[str]) -> str:
    return "; ".join(f"{a} -> {b} (line {graph[a][b][0]})"
                     for a in component for b in component if b in graph[a])


def write_package(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root


def test_the_checker_finds_cycles_it_is_shown(tmp_path):
    """Three cycles written on purpose, of three kinds: top-level imports two modules deep, a
    function-level import, and a submodule importing a name from its own package's
    ``__init__``, which imports that submodule; and a chain that is no cycle."""
    root = write_package(tmp_path, {
        "pkg/__init__.py": "",
        "pkg/a.py": "from .b import x\n",
        "pkg/b.py": "from pkg.c import y\nx = 1\n",
        "pkg/c.py": "def f():\n    from . import a\ny = 2\n",
        "pkg/sub/__init__.py": "from .leaf import z\n",
        "pkg/sub/leaf.py": "def g():\n    from . import helper\nz = 3\n",
        "pkg/sub/deep/__init__.py": "",
        "pkg/sub/deep/low.py": "from ...errors import E\n",
        "pkg/errors.py": "E = 0\n",
        "pkg/top.py": "from .sub.deep import low\nimport pkg.errors\n",
    })
    graph = import_graph(root, "pkg")
    assert graph["pkg.sub.deep.low"] == {"pkg.errors": [1]}
    assert graph["pkg.top"] == {"pkg.sub.deep.low": [1], "pkg.errors": [2]}
    assert sorted(cycles(graph)) == [["pkg.a", "pkg.b", "pkg.c"], ["pkg.sub", "pkg.sub.leaf"]]


def test_no_import_cycles():
    graph = import_graph(SRC, PACKAGE)
    assert len(graph) > 50 and "forceclosure.synthesis.planar" in graph
    # the edges the analysis is known to need are seen (so the graph is not empty by accident)
    assert ("forceclosure.synthesis.planar.two_fingers"
            in graph["forceclosure.synthesis.planar.two_sided_cone"])
    assert "forceclosure.analysis.batch_analysis" in graph["forceclosure.analysis.two_finger"]
    found = cycles(graph)
    assert not found, "import cycles: " + " | ".join(describe(graph, c) for c in found)


def test_geometry_imports_nothing_above_it():
    """A geometry layer (clipping, frames, cones, sampling) imports nothing of the package
    but errors and tolerances, once it exists."""
    graph = import_graph(SRC, PACKAGE)
    allowed = {"forceclosure.errors", "forceclosure.tolerance"}
    layer = [m for m in graph if m == "forceclosure.geometry"
             or m.startswith("forceclosure.geometry.")]
    if not (SRC / PACKAGE / "geometry").is_dir():
        assert not layer
        return
    for module in layer:
        above = {m for m in graph[module] if m not in allowed and m not in layer}
        assert not above, f"{module} imports {sorted(above)}"


#: The layers, bottom up: a module imports only from its own layer and those below (the package's
#: ``__init__``, the lazy facade of public names, and ``__main__`` stand outside). ``files`` (read
#: a user's file, write one atomically, a run's results folder) imports only ``errors``, so every
#: layer may use it, as may ``schemas`` (the shipped JSON schemas), ``extras`` (the optional
#: packages, imported on use), ``verdicts`` (the verdicts' words and codes) and ``lazy`` (the
#: facades' names imported on first use); the grasp formats stay above, in ``io``.
LAYERS = [
    ["errors", "tolerance", "files", "schemas", "extras", "verdicts", "lazy"],
    ["geometry"],
    ["contacts", "kernels"],
    ["objects", "simulators"],
    ["analysis"],
    ["synthesis"],
    ["gripper"],  # may use synthesis (antipodal sampling uses its patches), never the reverse
    ["io"],
    ["pictures"],  # draws grasps as the exports write them (io.export)
    ["datasets"],  # one job over many objects: synthesis, analysis, gripper labels, pictures
    ["app"],
]


def layer_of(module: str, package: str, layers: list[list[str]]) -> int | None:
    """The index of the layer ``module`` is in (its longest listed prefix), or None."""
    rest = module.removeprefix(package + ".")
    best: tuple[int, int] | None = None
    for rank, names in enumerate(layers):
        for name in names:
            if (rest == name or rest.startswith(name + ".")) and (best is None
                                                                  or len(name) > best[1]):
                best = (rank, len(name))
    return None if best is None else best[0]


def upward_imports(graph: dict[str, dict[str, list[int]]], package: str,
                   layers: list[list[str]]) -> list[str]:
    """Every import of a module in a higher layer than the importer's, as text."""
    found = []
    for a, edges in sorted(graph.items()):
        ra = layer_of(a, package, layers)
        if ra is None:
            continue
        for b, lines in sorted(edges.items()):
            rb = layer_of(b, package, layers)
            if rb is not None and rb > ra:
                found.append(f"{a} -> {b} (line {lines[0]})")
    return found


def test_the_layer_checker_finds_what_it_is_shown(tmp_path):
    """An upward import written on purpose, at module level and inside a function, is found;
    imports down the layers and within one are not."""
    root = write_package(tmp_path, {
        "pkg/__init__.py": "from .top import run\n",
        "pkg/errors.py": "E = 0\n",
        "pkg/low/__init__.py": "",
        "pkg/low/leaf.py": "from ..errors import E\nfrom . import other\n",
        "pkg/low/other.py": "def f():\n    from ..top.cli import run\n",
        "pkg/mid.py": "from .low.leaf import E\nfrom .top import cli\n",
        "pkg/top/__init__.py": "",
        "pkg/top/cli.py": "from ..mid import E\nrun = 1\n",
    })
    layers = [["errors"], ["low"], ["mid"], ["top"]]
    assert layer_of("pkg.low.leaf", "pkg", layers) == 1 and layer_of("pkg", "pkg", layers) is None
    assert upward_imports(import_graph(root, "pkg"), "pkg", layers) == [
        "pkg.low.other -> pkg.top.cli (line 2)", "pkg.mid -> pkg.top.cli (line 2)"]


def test_every_module_is_in_a_layer():
    unplaced = [m for m in module_files(SRC, PACKAGE)
                if m not in (PACKAGE, f"{PACKAGE}.__main__")
                and layer_of(m, PACKAGE, LAYERS) is None]
    assert not unplaced, f"modules in no layer: {unplaced}"
    for name in ["files", "geometry", "analysis", "synthesis", "synthesis/planar",
                 "synthesis/spatial", "synthesis/mesh", "gripper", "io", "pictures", "app"]:
        assert (SRC / PACKAGE / name / "__init__.py").is_file(), name


def test_layers_import_nothing_above_them():
    graph = import_graph(SRC, PACKAGE)
    # edges known to exist, so that a graph which lost its edges cannot pass
    assert "forceclosure.kernels.theorem1" in graph["forceclosure.analysis.batch"]
    assert "forceclosure.analysis.closure" in graph["forceclosure.app.cmd_demo"]
    assert "forceclosure.synthesis.spatial.patches" in graph["forceclosure.gripper.antipodal"]
    found = upward_imports(graph, PACKAGE, LAYERS)
    assert not found, "imports up the layers: " + "; ".join(found)


def test_analysis_imports_no_synthesis_gripper_pictures_io_or_app():
    graph = import_graph(SRC, PACKAGE)
    above = ("synthesis", "gripper", "pictures", "io", "app")
    analysis = [m for m in graph if m.startswith("forceclosure.analysis")]
    assert len(analysis) == 11  # the package and its 10 modules (robust, on jaw poses: gripper)
    for module in analysis:
        bad = sorted(m for m in graph[module]
                     if any(m.startswith(f"forceclosure.{a}") for a in above))
        assert not bad, f"{module} imports {bad}"


def test_nothing_in_the_library_imports_the_app():
    graph = import_graph(SRC, PACKAGE)
    library = [m for m in graph if not m.startswith("forceclosure.app")
               and m != "forceclosure.__main__"]
    assert "forceclosure.app.cli" in graph["forceclosure.__main__"]
    bad = {m: sorted(b for b in graph[m] if b.startswith("forceclosure.app")) for m in library}
    assert not any(bad.values()), {m: b for m, b in bad.items() if b}


def public_modules() -> list[str]:
    return sorted(name for name, path in module_files(SRC, PACKAGE).items()
                  if path.name == "__init__.py"
                  or not (path.name.startswith("_") or path.name == "__main__.py"))


@pytest.mark.parametrize("name", public_modules())
def test_every_public_module_declares_all(name):
    module = importlib.import_module(name)
    assert isinstance(getattr(module, "__all__", None), list | tuple), f"{name} has no __all__"
    names = list(module.__all__)
    assert len(names) == len(set(names)), f"{name}.__all__ repeats a name"
    missing = [n for n in names if not hasattr(module, n)]
    assert not missing, f"{name}.__all__ names what it does not have: {missing}"


def is_private(name: str) -> bool:
    """``_name`` (not ``__dunder__``): a name its module keeps to itself."""
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def private_imports(root: Path, package: str) -> list[str]:
    """Every private name one module of ``package`` takes from another, as text: ``from m
    import _x`` (``_x`` a name or a private module), and ``m._x`` on a module ``m`` imported as
    a name (``from pkg import m``, ``import pkg.m as m``)."""
    modules = module_files(root, package)
    found = []
    for name, path in modules.items():
        here = name if path.name == "__init__.py" else name.rpartition(".")[0]
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        bound: dict[str, str] = {}  # local name -> module of the package it is bound to
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = here.split(".")
                    base = base[: len(base) - (node.level - 1)]
                    start = ".".join(base + ([node.module] if node.module else []))
                else:
                    start = node.module or ""
                if start != package and not start.startswith(package + "."):
                    continue
                for a in node.names:
                    if f"{start}.{a.name}" in modules:
                        bound[a.asname or a.name] = f"{start}.{a.name}"
                    if is_private(a.name) and start != name:
                        found.append(f"{name} (line {node.lineno}): from {start} import {a.name}")
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.asname and a.name in modules:
                        bound[a.asname] = a.name
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id in bound and bound[node.value.id] != name
                    and is_private(node.attr)):
                found.append(f"{name} (line {node.lineno}): {bound[node.value.id]}.{node.attr}")
    return found


def test_the_private_name_checker_finds_what_it_is_shown(tmp_path):
    """Private names taken across modules on purpose (a relative and an absolute import, one
    inside a function, a private module, an attribute of an imported module) are found; a
    module's own private names, dunders and public names are not."""
    root = write_package(tmp_path, {
        "pkg/__init__.py": "__version__ = '1'\n",
        "pkg/low.py": "_secret = 1\nshared = 2\n\n\ndef _helper():\n    return _secret\n",
        "pkg/_hidden.py": "x = 1\n",
        "pkg/a.py": "from .low import _secret, shared\n",
        "pkg/b.py": "def f():\n    from pkg.low import _helper\n    return _helper()\n",
        "pkg/c.py": "from . import _hidden, __version__\nfrom . import low\ny = low._secret\n",
        "pkg/d.py": "import pkg.low as low\nfrom .low import shared\nz = low.shared\n",
        "pkg/e.py": "import pkg.low as low\nw = low._helper()\n",
    })
    assert private_imports(root, "pkg") == [
        "pkg.a (line 1): from pkg.low import _secret",
        "pkg.b (line 2): from pkg.low import _helper",
        "pkg.c (line 1): from pkg import _hidden",
        "pkg.c (line 3): pkg.low._secret",
        "pkg.e (line 2): pkg.low._helper",
    ]


def test_no_private_name_crosses_modules():
    """A name with a leading underscore stays in its module: one used elsewhere in the package
    is made public there (named without the underscore, documented; out of ``__all__`` when
    only the package uses it) or moved."""
    found = private_imports(SRC, PACKAGE)
    assert not found, "private names used across modules: " + "; ".join(found)
