"""Reading a URDF link's geometry as the file means it.

A link's shape is the union of all its ``<collision>`` elements, each a
``<geometry>`` placed in the link's frame by its ``<origin xyz rpy>``:

* ``<mesh filename scale>``: the file's triangles (read by trimesh without
  its processing), multiplied by ``scale`` (one number, or one per axis),
  then placed;
* ``<box size="x y z">``, centred on the origin;
* ``<cylinder radius length>``, its axis along z, centred;
* ``<sphere radius>``.

``rpy`` is the URDF convention: fixed-axis roll about x, then pitch about y,
then yaw about z, so a point ``p`` of the geometry lands at
``Rz(yaw) Ry(pitch) Rx(roll) p + xyz``. Cylinders and spheres are curved:
they are tessellated with every vertex on the true surface and every facet
within :data:`TESSELLATION_TOLERANCE` (1e-3) of the radius from it (the
chord deviation), so the mesh lies inside the true shape and holds at least
``(1 - 1e-3)**2`` (cylinder) or ``(1 - 1e-3)**3`` (sphere) of its volume.
Cylinders have :data:`CYLINDER_SECTIONS` sides (a multiple of 4, starting
on the x axis, so their bounds are exact); spheres are trimesh icospheres
(their six axis points are vertices, so their bounds are exact too). The
object's ``warnings`` say when a curved primitive was tessellated.

A link without ``<collision>`` elements is read from its ``<visual>`` ones,
with the warning "no collision geometry; read the visual one". A robot with
several links that carry geometry is refused unless ``part`` names one.
All pieces are concatenated into one triangle set: pieces that do not touch
become separate shells; overlapping ones are left as they are (several
shells), for :class:`~forceclosure.objects.polyhedron.Polyhedron` to deal with.

Mesh file names: ``package://pkg/rest`` is resolved as ROS does: the
package's folder is a folder above the URDF whose ``package.xml`` names
``pkg`` (or a folder named ``pkg`` with a ``package.xml``), or one found in
``ROS_PACKAGE_PATH``; a subfolder ``pkg`` of the URDF's own folder counts too
(pybullet's ``xarm``). Failing those, ``rest`` is taken relative to the
URDF's folder. ``file://`` URIs and plain paths are relative to the URDF's
folder unless absolute. A mesh that resolves (``..`` and symbolic links
followed) outside its package's folder (for plain names: the ROS package the
URDF is in, so ``pkg/urdf/r.urdf`` may name ``../meshes/a.obj``; else the
URDF's folder) is refused in one line naming it, unless
``allow_outside_meshes=True``. Blank lines before the XML
declaration (strictly not XML; pybullet's ``biped2d_pybullet.urdf`` has
them) are skipped.

Why not yourdfpy: it reads links and geometry types well, but not
faithfully enough to be trusted without a refusal path. Checked on
yourdfpy 0.0.60: it silently recovers truncated XML (a half-written file
loads as a robot with whatever came before the cut); it turns ``<origin>``
into a matrix from the first three numbers, so ``xyz="1 2 3 4"`` or a
four-number ``rpy`` load without complaint; it accepts ``<box size="1 2">``;
and an empty ``<geometry/>`` raises ``IndexError``. Since the checks need
the raw attribute text anyway, the reader here is a small ElementTree one
that checks every number it reads and refuses, in one line naming the file,
the link, the element and the field, whatever it cannot read exactly.
"""

from __future__ import annotations

import math
import os
import re
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path
from urllib.parse import unquote, urlsplit

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError, first_line
from .meshfile import MESH_SUFFIXES, read_mesh_arrays
from .polyhedron import Polyhedron

__all__ = [
    "CYLINDER_SECTIONS",
    "CYLINDER_TURN",
    "TESSELLATION_TOLERANCE",
    "GeometryPiece",
    "box_mesh",
    "check_mesh_inside",
    "cylinder_mesh",
    "link_geometry",
    "mesh_files",
    "origin_transform",
    "polyhedron_from_urdf",
    "resolve_mesh_filename",
    "sphere_mesh",
]

TESSELLATION_TOLERANCE = 1e-3
"""Largest distance from a tessellated cylinder or sphere to its true surface, per unit radius."""

CYLINDER_SECTIONS = 4 * math.ceil(math.pi / math.acos(1 - TESSELLATION_TOLERANCE) / 4)
"""Sides of a tessellated cylinder: the least multiple of 4 whose chord deviation
``1 - cos(pi / n)`` is within the tolerance (72)."""

_LISTED = 20  # links named in a refusal before "..."


def origin_transform(xyz: NDArray[np.float64] | list[float],
                     rpy: NDArray[np.float64] | list[float]) -> NDArray[np.float64]:
    """The 4×4 transform of a URDF ``<origin xyz rpy>``: ``Rz(yaw) Ry(pitch) Rx(roll)``, then
    the translation.

    Examples
    --------
    >>> T = origin_transform([1, 0, 0], [0, 0, np.pi / 2])  # a quarter turn about z
    >>> np.round(T @ [1, 0, 0, 1], 12).tolist()
    [1.0, 1.0, 0.0, 1.0]
    """
    roll, pitch, yaw = (float(a) for a in rpy)
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch),
                              math.sin(pitch), math.cos(yaw), math.sin(yaw))
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    transform = np.eye(4)
    transform[:3, :3] = rz @ ry @ rx
    transform[:3, 3] = np.asarray(xyz, dtype=float)
    return transform


def box_mesh(size: NDArray[np.float64] | list[float]) -> tuple[NDArray[np.float64],
                                                              NDArray[np.int64]]:
    """A box centred on the origin: 8 vertices, 12 triangles facing out.

    Examples
    --------
    >>> V, T = box_mesh([1, 2, 3])
    >>> V.min(axis=0).tolist(), V.max(axis=0).tolist(), T.shape
    ([-0.5, -1.0, -1.5], [0.5, 1.0, 1.5], (12, 3))
    """
    import trimesh

    mesh = trimesh.creation.box(extents=np.asarray(size, dtype=float))
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)


def cylinder_mesh(radius: float, length: float) -> tuple[NDArray[np.float64],
                                                         NDArray[np.int64]]:
    """A cylinder along z, centred, with :data:`CYLINDER_SECTIONS` sides inscribed in the circle.

    Examples
    --------
    >>> V, T = cylinder_mesh(1.0, 2.0)
    >>> V.min(axis=0).tolist(), V.max(axis=0).tolist()
    ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])
    """
    import trimesh

    mesh = trimesh.creation.cylinder(radius=radius, height=length, sections=CYLINDER_SECTIONS)
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)


@lru_cache(maxsize=1)
def _unit_sphere() -> tuple[NDArray[np.float64], NDArray[np.int64], float]:
    """The coarsest icosphere whose facets are within the tolerance of the unit sphere, and
    how far the sphere's normal turns from a facet's over it (at most at a corner, where it
    is the corner's radius)."""
    import trimesh

    for level in range(1, 8):
        mesh = trimesh.creation.icosphere(subdivisions=level, radius=1.0)
        V, T = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)
        normals = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        if 1 - np.abs(np.einsum("ij,ij->i", normals, V[T[:, 0]])).min() <= TESSELLATION_TOLERANCE:
            corner = V[T] / np.linalg.norm(V[T], axis=2, keepdims=True)
            turn = np.arccos(np.clip(np.einsum("ikj,ij->ik", corner, normals), -1, 1)).max()
            return V, T, float(turn) * (1 + 1e-9) + 1e-12
    raise AssertionError("no icosphere is fine enough")  # pragma: no cover


#: How far a cylinder's normal turns from a side facet's over it: half the facet's angle.
CYLINDER_TURN = math.pi / CYLINDER_SECTIONS * (1 + 1e-9)


def sphere_mesh(radius: float) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """A sphere centred on the origin, an icosphere inscribed within the tolerance.

    Examples
    --------
    >>> V, T = sphere_mesh(2.0)
    >>> bool(np.allclose(np.linalg.norm(V, axis=1), 2.0)), V.max(axis=0).tolist()
    (True, [2.0, 2.0, 2.0])
    """
    V, T, _ = _unit_sphere()
    return V * radius, T.copy()


@dataclass(frozen=True)
class GeometryPiece:
    """One ``<collision>`` (or ``<visual>``) geometry, placed in the link's frame.

    Attributes
    ----------
    where : str
        ``collision 2`` or ``visual 1``: which element of the link, counted from 1.
    kind : str
        ``mesh``, ``box``, ``cylinder`` or ``sphere``.
    vertices : (n, 3) array
        In the link's frame (origin and scale applied).
    triangles : (m, 3) int array
    mesh_file : Path or None
        The mesh file read, for a ``mesh``.
    turn : float
        Radians the true surface's normal turns from the facets' (a tessellated
        cylinder or sphere; 0 for boxes and meshes).
    """

    where: str
    kind: str
    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    mesh_file: Path | None = None
    turn: float = 0.0


def urdf_numbers(text: str | None, count: tuple[int, ...], what: str, where: str,
                 positive: bool = False) -> NDArray[np.float64]:
    """``count`` (one of) finite numbers from an attribute's text, or one line why not."""
    words = {1: "one number", 3: "three numbers"}
    wanted = words[count[0]]
    other = f" (or {words[count[1]].split()[0]})" if len(count) > 1 else ""

    def refuse(adjective: str) -> InputError:
        head, _, tail = wanted.partition(" ")
        return InputError(f"{where}: {what} {text!r} is not {head} {adjective}{tail}{other}")

    if text is None:
        raise InputError(f"{where}: {what} is missing")
    try:
        values = np.array([float(v) for v in text.split()])
    except ValueError:
        raise refuse("") from None
    if len(values) not in count:
        raise refuse("")
    if not np.all(np.isfinite(values)):
        raise refuse("finite ")
    if positive and np.any(values <= 0):
        raise refuse("positive ")
    return values


#: How deep below a ``ROS_PACKAGE_PATH`` entry packages are looked for, and how many folders
#: at most are looked at (a workspace is crawled as ``rospack`` does, within bounds).
_CRAWL_DEPTH, _CRAWL_FOLDERS = 6, 20_000

#: A ROS package name as REP 144 (and, more loosely, older packages) spell them.
_PACKAGE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")


def _manifest_name(folder: Path) -> str | None:
    """The ``<name>`` in ``folder/package.xml``, or None (no manifest, or not readable)."""
    manifest = folder / "package.xml"
    try:
        if not manifest.is_file():
            return None
        name = ET.parse(manifest).getroot().findtext("name")
    except (ET.ParseError, OSError, RecursionError):
        return None
    return None if name is None else name.strip()


def _is_package(folder: Path, package: str) -> bool:
    """Whether ``folder`` is package ``package``: its ``package.xml`` names it, or the folder
    has that name and a ``package.xml``."""
    name = _manifest_name(folder)
    return name == package or (name is not None and folder.name == package)


def _ros_package_path(package: str) -> list[Path]:
    """Package ``package``'s folders under the ``ROS_PACKAGE_PATH`` entries, first entry first
    (a crawl that stops at packages, skips hidden folders and is bounded; remembered per
    package and value of the variable, so a dataset of URDFs crawls once)."""
    return list(_crawl(package, os.environ.get("ROS_PACKAGE_PATH", "")))


@lru_cache(maxsize=256)
def _crawl(package: str, entries: str) -> tuple[Path, ...]:
    found: list[Path] = []
    seen = 0
    for entry in entries.split(os.pathsep):
        if not entry or not Path(entry).is_dir():
            continue
        level = [Path(entry)]
        for _ in range(_CRAWL_DEPTH):
            below = []
            for folder in level:
                seen += 1
                if seen > _CRAWL_FOLDERS:
                    return tuple(found)
                if _manifest_name(folder) is not None:  # a package: not crawled into
                    if _is_package(folder, package):
                        found.append(folder)
                    continue
                try:
                    below.extend(sorted(c for c in folder.iterdir()
                                        if c.is_dir() and not c.name.startswith(".")))
                except OSError:
                    continue
            level = below
    return tuple(found)


def _enclosing_package(folder: Path) -> Path | None:
    """The nearest folder at or above ``folder`` with a ``package.xml`` (the ROS package the
    URDF belongs to), or None."""
    for ancestor in [folder, *folder.parents]:
        if _manifest_name(ancestor) is not None:
            return ancestor
    return None


def _package_roots(package: str, folder: Path) -> Iterator[Path]:
    """Folders that are package ``package`` as ROS finds it, nearest first.

    Searching up from the URDF's ``folder`` (resolved): a folder whose
    ``package.xml`` names the package, or a folder of the package's name with
    a ``package.xml``; a package in the folder holding the URDF's own package
    (a workspace's ``src/``, crawled as for ``ROS_PACKAGE_PATH``); the
    ``ROS_PACKAGE_PATH`` entries.
    Besides, without any ``package.xml``, the usual layouts: a subfolder
    ``package`` of the URDF's folder (pybullet's ``xarm`` and ``franka_panda``
    lay their meshes so) that does not lead out of that folder by a symbolic
    link, and the URDF's folder or, for ``package/urdf/x.urdf``, its parent,
    when named ``package``. Other ancestors merely named like the package are
    not packages: ``/`` is everyone's ancestor.
    """
    def candidates() -> Iterator[Path]:
        inside = folder / package
        if inside.is_dir() and inside.resolve().is_relative_to(folder):
            yield inside
        yield from (a for a in [folder, *folder.parents] if _is_package(a, package))
        if folder.name == package:
            yield folder
        elif folder.name == "urdf" and folder.parent.name == package:
            yield folder.parent
        enclosing = _enclosing_package(folder)
        if enclosing is not None and enclosing.parent != enclosing:  # its workspace
            yield from _crawl(package, str(enclosing.parent))
        yield from _ros_package_path(package)

    seen: set[Path] = set()
    for root in candidates():  # lazily: a workspace is crawled only when nearer ones fail
        if root not in seen:
            seen.add(root)
            yield root


def _resolve(filename: str, urdf: Path) -> tuple[Path, Path]:
    """Where a mesh ``filename`` is, and the folder it may not leave (the ``package://``
    package's; for other names the ROS package the URDF is in, else the URDF's folder)."""
    folder = urdf.parent
    enclosing = _enclosing_package(folder.resolve())
    confined = enclosing if enclosing is not None else folder
    if filename.startswith("package://"):
        package, _, rest = filename[len("package://"):].partition("/")
        rest = unquote(rest)
        if not package or not rest:
            raise InputError(f"{urdf.name}: mesh {filename!r}: a package:// address needs a "
                             "package name and a path in it")
        if not _PACKAGE_NAME.fullmatch(package) or package.strip(".") == "":
            raise InputError(f"{urdf.name}: mesh {filename!r}: {package!r} is not a package "
                             "name")
        for root in _package_roots(package, folder.resolve()):
            if (root / rest).is_file():
                return root / rest, root
        return folder / rest, folder
    if filename.startswith("file://"):
        parts = urlsplit(filename)
        path = unquote(parts.path)
        if parts.netloc and parts.netloc != "localhost":  # file://meshes/a.obj: a relative path
            path = unquote(parts.netloc) + path
        return (Path(path) if Path(path).is_absolute() else folder / path), confined
    scheme = urlsplit(filename).scheme
    if len(scheme) > 1:  # not a Windows drive letter
        raise InputError(f"{urdf.name}: mesh {filename!r}: cannot read {scheme}:// addresses "
                         "(package://, file:// and paths are read)")
    return folder / filename, confined


def resolve_mesh_filename(filename: str, urdf: Path) -> Path:
    """Where a URDF's mesh ``filename`` is: ``package://``, ``file://`` or a path.

    A ``package://pkg/rest`` whose package folder is not found, or lacks
    ``rest``, falls back to ``rest`` in the URDF's folder. The path returned
    may not exist (the caller says so, naming it), and may lie outside the
    URDF's folder (:func:`check_mesh_inside` says whether it does).

    Examples
    --------
    >>> resolve_mesh_filename("meshes/a.stl", Path("/robots/r.urdf")).as_posix()
    '/robots/meshes/a.stl'
    >>> resolve_mesh_filename("file:///data/a.obj", Path("/robots/r.urdf")).as_posix()
    '/data/a.obj'
    """
    return _resolve(filename, urdf)[0]


def check_mesh_inside(filename: str, urdf: Path, where: str | None = None) -> Path:
    """The mesh file a URDF names, refused in one line when it lies outside the URDF's folder
    (or, for ``package://``, the package's folder), symbolic links followed.

    A URDF is data: one fetched from elsewhere must not make the reader open
    any mesh on the disk (``../../secret/a.stl``, ``/home/me/model.obj``, a
    link pointing out). Pass ``allow_outside_meshes=True`` to
    :func:`polyhedron_from_urdf` (``--allow-outside-meshes`` on the command
    line) for URDFs you trust that share meshes with others.

    Examples
    --------
    >>> import pybullet_data
    >>> urdf = Path(pybullet_data.getDataPath()) / "random_urdfs" / "000" / "000.urdf"
    >>> check_mesh_inside("000.obj", urdf).name
    '000.obj'
    >>> try:
    ...     check_mesh_inside("../001/001.obj", urdf)
    ... except InputError as e:
    ...     print(str(e).split(" folder ")[0])
    000.urdf: its mesh '../001/001.obj' is outside the URDF's
    """
    where = where or urdf.name
    path, root = _resolve(filename, urdf)
    try:
        real, top = path.resolve(), root.resolve()
    except (RuntimeError, OSError) as e:  # a symbolic link loop (RuntimeError before 3.13)
        raise InputError(f"{where}: its mesh {filename!r} cannot be followed: "
                         f"{first_line(e)}") from None
    if not real.is_relative_to(top):
        kind = "URDF's" if root == urdf.parent else "package's"
        raise InputError(f"{where}: its mesh {filename!r} is outside the {kind} folder "
                         f"{top}; pass allow_outside_meshes=True (--allow-outside-meshes) "
                         "to read it")
    return path


def _piece(element: ET.Element, urdf: Path, link: str, which: str,
           allow_outside_meshes: bool = False) -> GeometryPiece:
    """The geometry of one ``<collision>`` or ``<visual>`` element, placed by its origin."""
    where = f"{urdf.name}: link {link}, {which}"
    origins = element.findall("origin")
    if len(origins) > 1:
        raise InputError(f"{where}: has {len(origins)} <origin> elements; one is allowed")
    xyz = urdf_numbers(origins[0].get("xyz", "0 0 0") if origins else "0 0 0", (3,),
                       "origin xyz", where)
    rpy = urdf_numbers(origins[0].get("rpy", "0 0 0") if origins else "0 0 0", (3,),
                       "origin rpy", where)
    geometries = element.findall("geometry")
    if len(geometries) != 1:
        raise InputError(f"{where}: has {len(geometries)} <geometry> elements; one is needed")
    shapes = list(geometries[0])
    if len(shapes) != 1:
        raise InputError(f"{where}: its <geometry> holds {len(shapes)} shapes; one is needed")
    shape = shapes[0]
    kind = shape.tag.rsplit("}", 1)[-1] if isinstance(shape.tag, str) else "?"
    mesh_file = None
    turn = 0.0  # how far the true surface's normal turns from the facets'
    if kind == "box":
        V, T = box_mesh(urdf_numbers(shape.get("size"), (3,), "box size", where, positive=True))
    elif kind == "cylinder":
        radius = urdf_numbers(shape.get("radius"), (1,), "cylinder radius", where, positive=True)
        length = urdf_numbers(shape.get("length"), (1,), "cylinder length", where, positive=True)
        V, T = cylinder_mesh(float(radius[0]), float(length[0]))
        turn = CYLINDER_TURN
    elif kind == "sphere":
        V, T = sphere_mesh(float(urdf_numbers(shape.get("radius"), (1,), "sphere radius", where,
                                              positive=True)[0]))
        turn = _unit_sphere()[2]
    elif kind == "mesh":
        filename = shape.get("filename")
        if not filename:
            raise InputError(f"{where}: <mesh> has no filename")
        scale = urdf_numbers(shape.get("scale", "1 1 1"), (3, 1), "mesh scale", where,
                             positive=True)
        mesh_file = (resolve_mesh_filename(filename, urdf) if allow_outside_meshes
                     else check_mesh_inside(filename, urdf, where))
        if not mesh_file.is_file():
            hint = ""
            if filename.startswith("package://"):
                package = filename[len("package://"):].partition("/")[0]
                hint = (f"; no package {package!r} holds it (a folder above the URDF whose "
                        "package.xml names it, or one in ROS_PACKAGE_PATH)")
            raise InputError(f"{where}: its mesh {mesh_file.name} is missing ({filename!r}, "
                             f"looked for {mesh_file}){hint}")
        if mesh_file.suffix.lower() not in MESH_SUFFIXES:
            raise InputError(f"{where}: its mesh {mesh_file.name} is not a mesh file "
                             f"({', '.join(MESH_SUFFIXES)})")
        try:
            V, T = read_mesh_arrays(mesh_file)
        except InputError as e:
            raise e.within(where) from None
        V = V * scale
    else:
        raise InputError(f"{where}: unknown geometry <{kind}> (box, cylinder, sphere and mesh "
                         "are read)")
    transform = origin_transform(xyz, rpy)
    placed = V @ transform[:3, :3].T + transform[:3, 3]
    return GeometryPiece(which, kind, placed, T, mesh_file, turn)


def _label(link: ET.Element, index: int) -> str:
    name = link.get("name")
    return repr(name) if name else f"{index + 1} (unnamed)"


def robot_element(path: Path) -> ET.Element:
    """The ``<robot>`` element of a URDF file, or one line saying why there is none."""
    try:  # blank lines before the XML declaration (pybullet's biped2d has them) mean nothing
        root = ET.fromstring(path.read_bytes().lstrip(b" \t\r\n"))
    except ET.ParseError as e:
        raise InputError(f"{path.name}: not a URDF file: {first_line(e)}") from None
    if root.tag != "robot":
        raise InputError(f"{path.name}: not a URDF file: the root element is <{root.tag}>, "
                         "not <robot>")
    return root


def mesh_files(path: Path) -> list[Path]:
    """Every mesh file a URDF names, in any link, collision or visual (for listing what a
    URDF stands for, e.g. so that ``forceclosure dataset`` does not take them again); names
    that cannot be resolved are left out.

    Examples
    --------
    >>> import pybullet_data
    >>> [p.name for p in mesh_files(Path(pybullet_data.getDataPath()) / "duck_vhacd.urdf")]
    ['duck.obj', 'duck_vhacd.obj']
    """
    found = []
    for mesh in robot_element(path).iter("mesh"):
        try:
            found.append(resolve_mesh_filename(mesh.get("filename", ""), path))
        except InputError:
            continue
    return found


def link_geometry(path: Path, part: str | None = None, *, allow_outside_meshes: bool = False
                  ) -> tuple[str, list[GeometryPiece], list[str]]:
    """The geometry pieces of the link ``part`` of a URDF (or of its only link with geometry).

    Returns the link's name, its pieces in the file's order (collision ones,
    or visual ones when it has no collision geometry) and the warnings. A mesh
    outside the URDF's folder is refused unless ``allow_outside_meshes``
    (:func:`check_mesh_inside`).

    Examples
    --------
    >>> import pybullet_data
    >>> urdf = Path(pybullet_data.getDataPath()) / "r2d2.urdf"
    >>> name, pieces, _ = link_geometry(urdf, part="right_leg")
    >>> name, [(p.where, p.kind) for p in pieces]
    ('right_leg', [('collision 1', 'box')])
    """
    root = robot_element(path)
    links = root.findall("link")
    if not links:
        raise InputError(f"{path.name}: the URDF has no <link>")
    with_collision = [i for i, link in enumerate(links) if link.find("collision") is not None]
    with_visual = [i for i, link in enumerate(links) if link.find("visual") is not None]
    candidates, kind = (with_collision, "collision") if with_collision else (with_visual,
                                                                           "visual")

    def listing(indices: list[int]) -> str:
        names = [links[i].get("name") or f"link {i + 1} (unnamed)" for i in indices]
        more = f", ... ({len(names) - _LISTED} more)" if len(names) > _LISTED else ""
        return ", ".join(names[:_LISTED]) + more

    if part is None:
        if not candidates:
            raise InputError(f"{path.name}: no link has collision or visual geometry")
        if len(candidates) > 1:
            raise InputError(f"{path.name}: {len(candidates)} links have {kind} geometry "
                             f"({listing(candidates)}); name one with part= (--part on the "
                             "command line)")
        index = candidates[0]
    else:
        named = [i for i, link in enumerate(links) if link.get("name") == part]
        if not named:
            raise InputError(f"{path.name}: no link named {part!r}; the links with {kind} "
                             f"geometry are: {listing(candidates) or 'none'}")
        if len(named) > 1:
            raise InputError(f"{path.name}: {len(named)} links are named {part!r}")
        index = named[0]
    link = links[index]
    label = _label(link, index)
    warnings = []
    elements = link.findall("collision")
    tag = "collision"
    if not elements:
        elements, tag = link.findall("visual"), "visual"
        if not elements:
            raise InputError(f"{path.name}: link {label} has no collision or visual geometry")
        warnings.append("no collision geometry; read the visual one")
    pieces = [_piece(e, path, label, f"{tag} {k + 1}", allow_outside_meshes)
              for k, e in enumerate(elements)]
    curved = [p.kind for p in pieces if p.kind in ("cylinder", "sphere")]
    if curved:
        counts = ", ".join(f"{curved.count(k)} {k}{'s' if curved.count(k) > 1 else ''}"
                           for k in ("cylinder", "sphere") if k in curved)
        warnings.append(f"tessellated {counts}: inscribed, within {TESSELLATION_TOLERANCE:g} of "
                        "the radius of the true surface")
    return link.get("name") or f"link {index + 1}", pieces, warnings


def polyhedron_from_urdf(path: Path, allow_open: bool = False, part: str | None = None, *,
                         allow_outside_meshes: bool = False) -> Polyhedron:
    """The polyhedron of a URDF link: all its collision geometry, each piece placed.

    Parameters
    ----------
    path : Path
        The ``.urdf`` file.
    allow_open : bool
        Accept open and non-manifold meshes (with a warning).
    part : str, optional
        The link to read; needed when several links carry geometry.
    allow_outside_meshes : bool
        Read meshes outside the URDF's folder (or its package's); refused by
        default (:func:`check_mesh_inside`).

    Examples
    --------
    >>> import pybullet_data
    >>> cube = polyhedron_from_urdf(Path(pybullet_data.getDataPath()) / "cube.urdf")
    >>> cube.name, round(cube.volume, 12), cube.bounds.tolist()
    ('cube', 1.0, [[-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]])
    """
    _, pieces, warnings = link_geometry(path, part, allow_outside_meshes=allow_outside_meshes)
    offsets = np.cumsum([0] + [len(p.vertices) for p in pieces[:-1]])
    vertices = np.concatenate([p.vertices for p in pieces])
    triangles = np.concatenate([p.triangles + offset
                                for p, offset in zip(pieces, offsets, strict=True)])
    # a tessellated cylinder or sphere: every proof narrows its cones by how far the facets'
    # normals are from the true surface's (all faces, to keep it simple and sound)
    polyhedron = Polyhedron.from_arrays(vertices, triangles, path.stem, allow_open,
                                        spread=max(p.turn for p in pieces))
    if not warnings:
        return polyhedron
    return replace(polyhedron, warnings=(*warnings, *polyhedron.warnings))
