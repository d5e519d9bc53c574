"""Reading URDF links as the file means them: every collision geometry, placed by its origin.

Ground truth is computed here by hand (closed-form bounds and volumes, rotation matrices
written out), or read independently: meshes loaded with trimesh directly and URDF origins
parsed by yourdfpy, for URDFs nobody here wrote (pybullet_data).
"""

import json
import math
import re
from pathlib import Path

import numpy as np
import pybullet_data
import pytest
import trimesh
import yourdfpy

from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.objects.io import load_object
from forceclosure.objects.urdf import TESSELLATION_TOLERANCE, origin_transform

DATA = Path(pybullet_data.getDataPath())
TOL = TESSELLATION_TOLERANCE

# a unit cube, centred, written the way a modeller's OBJ export writes one (faces counted from 1)
CUBE_OBJ = """# unit cube
v -0.5 -0.5 -0.5
v 0.5 -0.5 -0.5
v 0.5 0.5 -0.5
v -0.5 0.5 -0.5
v -0.5 -0.5 0.5
v 0.5 -0.5 0.5
v 0.5 0.5 0.5
v -0.5 0.5 0.5
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
"""

# the corner tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1): volume 1/6
TET_OBJ = """v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
"""


def robot(*links: str, name: str = "r") -> str:
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n' + "\n".join(links) + "\n</robot>\n"


def link(name: str, *elements: str) -> str:
    return f'<link name="{name}">' + "".join(elements) + "</link>"


def collision(shape: str, xyz: str = "0 0 0", rpy: str = "0 0 0", tag: str = "collision") -> str:
    return (f'<{tag}><origin xyz="{xyz}" rpy="{rpy}"/><geometry>{shape}</geometry></{tag}>')


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def rot_z(a):
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


def rot_y(a):
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


def rot_x(a):
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


# ---------------------------------------------------------------- URDFs written here

def test_two_pieces_each_placed_by_its_origin(tmp_path):
    """A unit box at x = +2 and a unit-cube mesh scaled by 2, turned 45° about z, at x = -3.

    Read as the old reader did (the first piece only, at the origin) this was a unit cube at
    the origin, volume 1."""
    write(tmp_path, "cube.obj", CUBE_OBJ)
    path = write(tmp_path, "two_boxes.urdf", robot(link(
        "boxes",
        collision('<box size="1 1 1"/>', xyz="2 0 0"),
        collision('<mesh filename="cube.obj" scale="2"/>', xyz="-3 0 0",
                  rpy=f"0 0 {math.pi / 4!r}"))))
    obj = load_object(path)
    h = math.sqrt(2)  # half the diagonal of the 2 x 2 square turned 45°
    assert np.allclose(obj.bounds, [[-3 - h, -h, -1], [2.5, h, 1]], atol=1e-12)
    assert obj.volume == pytest.approx(1 + 8, rel=1e-12)  # pieces apart: the sum
    assert obj.shells == 2 and obj.name == "two_boxes" and obj.watertight
    # the turned cube's corners are where the rotation puts them
    corners = np.array([[-3 + h, 0, 1], [-3, h, -1], [-3 - h, 0, 1], [-3, -h, -1]])
    assert all(np.min(np.linalg.norm(obj.vertices - c, axis=1)) < 1e-12 for c in corners)


def test_pieces_apart_sum_their_volumes_and_areas(tmp_path):
    """A box, a scaled tetrahedron and a sphere that do not touch: volume and area add up."""
    write(tmp_path, "tet.obj", TET_OBJ)
    path = write(tmp_path, "apart.urdf", robot(link(
        "l",
        collision('<box size="1 2 3"/>'),
        collision('<mesh filename="tet.obj" scale="3 3 3"/>', xyz="5 0 0"),
        collision('<sphere radius="0.5"/>', xyz="0 0 10"))))
    obj = load_object(path)
    sphere = 4 / 3 * math.pi * 0.5**3
    low = 6 + 27 / 6 + sphere * (1 - TOL) ** 3
    assert low <= obj.volume <= 6 + 27 / 6 + sphere
    tet_area = 9 * (3 / 2 + math.sqrt(3) / 2)  # three right triangles and an equilateral one
    box_area = 2 * (2 + 3 + 6)
    assert obj.area == pytest.approx(box_area + tet_area + 4 * math.pi * 0.25, rel=3 * TOL)
    assert obj.shells == 3


def test_mesh_scale_per_axis_and_origin(tmp_path):
    """scale "1 2 3" stretches the mesh first; rpy pitch 90° then turns (x, y, z) to (z, y, -x)."""
    write(tmp_path, "meshes/tet.obj", TET_OBJ)
    path = write(tmp_path, "tet.urdf", robot(link(
        "t", collision('<mesh filename="meshes/tet.obj" scale="1 2 3"/>', xyz="0.1 0.2 0.3",
                       rpy=f"0 {math.pi / 2!r} 0"))))
    obj = load_object(path)
    shift = np.array([0.1, 0.2, 0.3])
    expected = np.array([[0, 0, 0], [0, 0, -1], [0, 2, 0], [3, 0, 0]]) + shift
    assert np.allclose(np.sort(obj.vertices, axis=0), np.sort(expected, axis=0), atol=1e-12)
    assert obj.volume == pytest.approx(1 * 2 * 3 / 6, rel=1e-12)


def test_rpy_is_fixed_axis_roll_then_pitch_then_yaw(tmp_path):
    """rpy (90°, 90°, 0): roll about x first, so (0, 1, 0) -> (0, 0, 1) -> (1, 0, 0).
    Pitch first would give (0, 0, 1) instead."""
    write(tmp_path, "tet.obj", TET_OBJ)
    q = repr(math.pi / 2)
    path = write(tmp_path, "t.urdf", robot(link(
        "t", collision('<mesh filename="tet.obj"/>', rpy=f"{q} {q} 0"))))
    vertices = load_object(path).vertices
    expected = [[0, 0, 0], [0, 0, -1], [1, 0, 0], [0, -1, 0]]  # images of the four corners
    assert np.allclose(np.sort(vertices, axis=0), np.sort(expected, axis=0), atol=1e-12)


def test_origin_matrix_agrees_with_an_independent_parser(tmp_path):
    """Random origins: the transform here equals the matrix yourdfpy builds from the same
    <origin>, and Rz(yaw) Ry(pitch) Rx(roll) written out by hand."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        xyz, rpy = rng.uniform(-2, 2, 3), rng.uniform(-math.pi, math.pi, 3)
        text = robot(link("a", collision('<box size="1 1 1"/>',
                                         xyz=" ".join(repr(float(v)) for v in xyz),
                                         rpy=" ".join(repr(float(v)) for v in rpy))))
        path = write(tmp_path, "o.urdf", text)
        theirs = yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False,
                                    load_collision_meshes=False)
        ours = origin_transform(xyz, rpy)
        assert np.allclose(ours, theirs.robot.links[0].collisions[0].origin, atol=1e-12)
        assert np.allclose(ours[:3, :3], rot_z(rpy[2]) @ rot_y(rpy[1]) @ rot_x(rpy[0]),
                           atol=1e-12)


def test_cylinder_within_the_stated_tolerance(tmp_path):
    """A cylinder of radius 0.3 and length 2 turned by roll 90° so its axis lies along y."""
    r, length = 0.3, 2.0
    path = write(tmp_path, "cyl.urdf", robot(link(
        "c", collision(f'<cylinder radius="{r}" length="{length}"/>', xyz="1 2 3",
                       rpy=f"{math.pi / 2!r} 0 0"))))
    obj = load_object(path)
    true = math.pi * r * r * length
    assert true * (1 - TOL) ** 2 <= obj.volume <= true
    assert obj.volume == pytest.approx(true, rel=2 * TOL)
    assert np.allclose(obj.bounds, [[1 - r, 2 - 1, 3 - r], [1 + r, 2 + 1, 3 + r]], atol=1e-12)
    # inscribed: every vertex off the axis is on the curved surface
    radial = np.hypot(obj.vertices[:, 0] - 1, obj.vertices[:, 2] - 3)
    assert np.allclose(radial[radial > 1e-9], r, atol=1e-12)
    assert any("tessellated 1 cylinder" in w and f"{TOL:g}" in w for w in obj.warnings)


def test_sphere_within_the_stated_tolerance(tmp_path):
    r = 0.7
    path = write(tmp_path, "ball.urdf", robot(link(
        "s", collision(f'<sphere radius="{r}"/>', xyz="0 0 5"))))
    obj = load_object(path)
    true = 4 / 3 * math.pi * r**3
    assert true * (1 - TOL) ** 3 <= obj.volume <= true
    assert np.allclose(obj.bounds, [[-r, -r, 5 - r], [r, r, 5 + r]], atol=1e-12)
    centre = np.array([0, 0, 5])
    assert np.allclose(np.linalg.norm(obj.vertices - centre, axis=1), r, atol=1e-12)
    # every facet is within the tolerance of the surface: its plane is >= r (1 - tol) away
    V, T = obj.vertices - centre, obj.triangles
    normals = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    assert np.einsum("ij,ij->i", normals, V[T[:, 0]]).min() >= r * (1 - TOL)
    assert any("tessellated 1 sphere" in w for w in obj.warnings)


def test_collision_is_read_not_visual(tmp_path):
    path = write(tmp_path, "cv.urdf", robot(link(
        "a", collision('<box size="1 1 1"/>', tag="visual"), collision('<box size="2 2 2"/>'))))
    obj = load_object(path)
    assert obj.volume == pytest.approx(8) and obj.warnings == ()


def test_no_collision_falls_back_to_visual_with_a_warning(tmp_path):
    path = write(tmp_path, "v.urdf", robot(link(
        "a", collision('<box size="1 2 4"/>', xyz="0 0 1", tag="visual"))))
    obj = load_object(path)
    assert obj.volume == pytest.approx(8, rel=1e-12)
    assert np.allclose(obj.bounds, [[-0.5, -1, -1], [0.5, 1, 3]])
    assert "no collision geometry; read the visual one" in obj.warnings


def test_package_uris(tmp_path):
    """package://my_pkg/meshes/tet.obj: the package folder is found upward from the URDF (a
    folder of that name with a package.xml, or a package.xml naming it), or is a subfolder of
    the URDF's folder; else the rest in the URDF's folder; else one line."""
    uri = '<mesh filename="package://my_pkg/meshes/tet.obj"/>'
    text = robot(link("t", collision(uri)))
    big = TET_OBJ.replace("v 1 0 0\nv 0 1 0\nv 0 0 1", "v 2 0 0\nv 0 2 0\nv 0 0 2")
    assert big != TET_OBJ  # a decoy, volume 8/6, where the fallback looks

    # 1. ws/src/my_pkg/urdf/r.urdf: the package is the folder my_pkg holding urdf/, with or
    # without a package.xml (not the decoy the fallback would read)
    write(tmp_path, "ws/src/my_pkg/meshes/tet.obj", TET_OBJ)
    write(tmp_path, "ws/src/my_pkg/urdf/meshes/tet.obj", big)
    urdf = write(tmp_path, "ws/src/my_pkg/urdf/r.urdf", text)
    assert load_object(urdf).volume == pytest.approx(1 / 6)
    write(tmp_path, "ws/src/my_pkg/package.xml", "<package><name>other</name></package>")
    assert load_object(urdf).volume == pytest.approx(1 / 6)
    # ... but a farther ancestor merely named my_pkg is not the package
    write(tmp_path, "my_pkg/robots/deep/meshes/tet.obj", big)
    urdf = write(tmp_path, "my_pkg/robots/deep/r.urdf", text)
    write(tmp_path, "my_pkg/meshes/tet.obj", TET_OBJ)
    assert load_object(urdf).volume == pytest.approx(8 / 6)

    # 1b. a sibling package of the URDF's own, in a workspace's src/ (no ROS_PACKAGE_PATH)
    write(tmp_path, "ws1/src/robot/package.xml", "<package><name>robot</name></package>")
    write(tmp_path, "ws1/src/parts/package.xml", "<package><name>my_pkg</name></package>")
    write(tmp_path, "ws1/src/parts/meshes/tet.obj", TET_OBJ)
    urdf = write(tmp_path, "ws1/src/robot/urdf/r.urdf", text)
    assert load_object(urdf).volume == pytest.approx(1 / 6)

    # 2. the folder has another name, its package.xml says my_pkg
    write(tmp_path, "ws2/checkout/package.xml",
          '<?xml version="1.0"?>\n<package format="2"><name>my_pkg</name>'
          "<version>1.0.0</version></package>")
    write(tmp_path, "ws2/checkout/meshes/tet.obj", TET_OBJ)
    urdf = write(tmp_path, "ws2/checkout/urdf/deep/r.urdf", text)
    assert load_object(urdf).volume == pytest.approx(1 / 6)

    # 3. the package folder is a sibling of the URDF (as in pybullet_data/xarm)
    write(tmp_path, "ws3/my_pkg/meshes/tet.obj", TET_OBJ)
    urdf = write(tmp_path, "ws3/r.urdf", text)
    assert load_object(urdf).volume == pytest.approx(1 / 6)

    # 4. no package folder: meshes/tet.obj next to the URDF
    write(tmp_path, "ws4/meshes/tet.obj", big)
    urdf = write(tmp_path, "ws4/r.urdf", text)
    assert load_object(urdf).volume == pytest.approx(8 / 6)

    # 5. nowhere: one line naming the file
    urdf = write(tmp_path, "ws5/r.urdf", text)
    with pytest.raises(InputError, match=r"r\.urdf: .*its mesh tet\.obj is missing") as e:
        load_object(urdf)
    assert "\n" not in str(e.value) and "package://my_pkg/meshes/tet.obj" in str(e.value)


PACKAGE_XML = '<?xml version="1.0"?>\n<package format="2"><name>pkg</name></package>'


def ros_layout(tmp_path: Path) -> Path:
    """ws/pkg (package.xml, meshes/box.obj: the unit cube, urdf/), and secret/secret.obj (the
    corner tetrahedron) beside ws: a file no URDF in the package may read."""
    write(tmp_path, "ws/pkg/package.xml", PACKAGE_XML)
    write(tmp_path, "ws/pkg/meshes/box.obj", CUBE_OBJ)
    write(tmp_path, "secret/secret.obj", TET_OBJ)
    return tmp_path / "ws" / "pkg"


def mesh_urdf(folder: Path, name: str, filename: str) -> Path:
    return write(folder, name, robot(link("l", collision(f'<mesh filename="{filename}"/>'))))


def test_ros_layout_reads_inside_the_package(tmp_path, monkeypatch):
    """pkg/urdf/r.urdf naming ../meshes/box.obj or package://pkg/meshes/box.obj reads the
    package's cube (volume 1); a URDF outside the package finds it through ROS_PACKAGE_PATH
    only."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    pkg = ros_layout(tmp_path)
    for i, filename in enumerate(("../meshes/box.obj", "package://pkg/meshes/box.obj",
                                  "package://pkg/urdf/../meshes/box.obj",
                                  "file://../meshes/box.obj")):
        urdf = mesh_urdf(pkg / "urdf", f"r{i}.urdf", filename)
        assert load_object(urdf).volume == pytest.approx(1.0), filename
    elsewhere = mesh_urdf(tmp_path / "robots", "r.urdf", "package://pkg/meshes/box.obj")
    with pytest.raises(InputError, match=r"missing .*no package 'pkg' holds it"):
        load_object(elsewhere)
    monkeypatch.setenv("ROS_PACKAGE_PATH", f"{tmp_path / 'nowhere'}:{tmp_path / 'ws'}")
    assert load_object(elsewhere).volume == pytest.approx(1.0)


def escapes(tmp_path: Path) -> list[str]:
    """Every way tried of naming secret/secret.obj from ws/pkg/urdf/r.urdf."""
    secret = tmp_path / "secret" / "secret.obj"
    top, *rest = secret.parts[1:]
    return [f"package://{top}/{'/'.join(rest)}",  # the top-level folder as "the package"
            "package://secret/secret.obj",  # an ancestor's sibling as the package
            "package://../secret/secret.obj",
            "package://../../../secret/secret.obj",
            "package://./../../secret/secret.obj",
            "package://pkg/../../secret/secret.obj",
            "package://pkg/%2e%2e/%2e%2e/secret/secret.obj",
            f"package://pkg/{secret}",  # package://pkg//abs/path
            "package://pkg/meshes/link.obj",  # a symbolic link out of the package
            "package://urdf/../../../secret/secret.obj",  # the URDF's subfolder, then up
            f"package://root/{top}/{'/'.join(rest)}",  # a subfolder linked to /
            "../../../secret/secret.obj",
            "meshes/../../../secret/secret.obj",
            str(secret),
            secret.as_uri()]


def test_every_package_escape_is_refused(tmp_path, monkeypatch):
    """No URDF in ws/pkg reads secret/secret.obj, whatever package:// or path it names: each
    is refused in one line naming it (and reads the tetrahedron only when allowed)."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    pkg = ros_layout(tmp_path)
    (pkg / "meshes" / "link.obj").symlink_to(tmp_path / "secret" / "secret.obj")
    write(tmp_path, "ws/pkg/urdf/urdf/keep.txt", "")  # a subfolder named like a package
    (pkg / "urdf" / "root").symlink_to("/")  # and one that leads out of the URDF's folder
    for i, filename in enumerate(escapes(tmp_path)):
        urdf = mesh_urdf(pkg / "urdf", f"e{i}.urdf", filename)
        with pytest.raises(InputError) as e:
            load_object(urdf)
        message = str(e.value)
        assert "\n" not in message and repr(filename) in message, message
        assert message.startswith(f"e{i}.urdf: "), message


def test_ros_package_path_is_confined_too(tmp_path, monkeypatch):
    """A package found through ROS_PACKAGE_PATH does not let package://pkg/../ out of it."""
    pkg = ros_layout(tmp_path)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws"))
    urdf = mesh_urdf(tmp_path / "robots", "r.urdf", "package://pkg/../../secret/secret.obj")
    with pytest.raises(InputError, match=r"is outside the package's folder") as e:
        load_object(urdf)
    assert str(pkg) in str(e.value)


def test_file_uris_and_paths(tmp_path):
    mesh = write(tmp_path, "elsewhere/tet.obj", TET_OBJ)
    write(tmp_path, "robots/parts/tet.obj", TET_OBJ)
    for filename in (mesh.as_uri(), str(mesh), "parts/tet.obj", "file://parts/tet.obj",
                     "./parts/../parts/tet.obj"):
        urdf = write(tmp_path, "robots/r.urdf",
                     robot(link("t", collision(f'<mesh filename="{filename}" scale="2"/>'))))
        assert load_object(urdf, allow_outside_meshes=True).volume == pytest.approx(8 / 6)
        if "elsewhere" in filename:  # outside the URDF's folder: refused unless allowed
            with pytest.raises(InputError, match="is outside the URDF's folder"):
                load_object(urdf)
        else:
            assert load_object(urdf).volume == pytest.approx(8 / 6), filename


TWO_LINKS = robot(link("boxes", collision('<box size="1 1 1"/>', xyz="2 0 0"),
                       collision('<box size="2 2 2"/>', xyz="-3 0 0")),
                  link("rod", collision('<box size="0.1 0.1 3"/>')),
                  link("bare", "<inertial/>"),
                  name="two")


def test_several_links_need_part(tmp_path):
    path = write(tmp_path, "two_boxes.urdf", TWO_LINKS)
    with pytest.raises(InputError) as e:
        load_object(path)
    assert str(e.value) == ("two_boxes.urdf: 2 links have collision geometry (boxes, rod); "
                            "name one with part= (--part on the command line)")
    assert load_object(path, part="boxes").volume == pytest.approx(9)
    assert load_object(path, part="rod").volume == pytest.approx(0.03)
    with pytest.raises(InputError, match=r"^two_boxes\.urdf: no link named 'wheel'; the links "
                                         r"with collision geometry are: boxes, rod$"):
        load_object(path, part="wheel")
    with pytest.raises(InputError, match=r"link 'bare' has no collision or visual geometry"):
        load_object(path, part="bare")
    with pytest.raises(InputError, match=r"part='boxes' names a URDF link .* has no parts"):
        load_object("cube", part="boxes")


BOX = '<box size="1 1 1"/>'
BAD = [
    ("<robot><link name='a'>", "not a URDF file"),
    ("<robt><link name='a'/></robt>", "not a URDF file: the root element is <robt>"),
    (robot(link("a", collision(BOX, xyz="1 2"))), "origin xyz '1 2' is not three numbers"),
    (robot(link("a", collision(BOX, xyz="1 2 3 4"))), "origin xyz '1 2 3 4' is not three numb"),
    (robot(link("a", collision(BOX, rpy="0 x 0"))), "origin rpy '0 x 0' is not three numbers"),
    (robot(link("a", collision(BOX, xyz="nan 0 0"))), "is not three finite numbers"),
    (robot(link("a", collision('<box size="1 -1 1"/>'))), "box size '1 -1 1' is not three pos"),
    (robot(link("a", collision('<box size="1 1"/>'))), "box size '1 1' is not three numbers"),
    (robot(link("a", collision('<sphere radius="0"/>'))), "sphere radius '0' is not one posit"),
    (robot(link("a", collision('<cylinder radius="1"/>'))), "cylinder length is missing"),
    (robot(link("a", collision('<capsule radius="1" length="2"/>'))),
     "unknown geometry <capsule>"),
    (robot(link("a", "<collision><geometry/></collision>")), "holds 0 shapes"),
    (robot(link("a", collision(BOX + BOX))), "holds 2 shapes"),
    (robot(link("a", "<collision><origin/></collision>")), "has 0 <geometry> elements"),
    (robot(link("a", collision('<mesh filename="gone.obj"/>'))), "its mesh gone.obj is missing"),
    (robot(link("a", collision('<mesh filename="m.txt"/>'))), "its mesh m.txt is not a mesh file"),
    (robot(link("a", collision('<mesh filename="empty.obj"/>'))), "empty.obj: the file is empty"),
    (robot(link("a", collision('<mesh/>'))), "<mesh> has no filename"),
    (robot(link("a", collision('<mesh filename="http://x.org/m.obj"/>'))),
     "cannot read http:// addresses"),
    (robot(link("a", collision('<mesh filename="package:///m.obj"/>'))),
     "a package:// address needs a package name"),
    (robot(link("a", collision('<mesh filename="m.obj" scale="1 1"/>'))),
     "mesh scale '1 1' is not three numbers (or one)"),
    (robot(link("a", collision('<mesh filename="m.obj" scale="0"/>'))),
     "mesh scale '0' is not three positive numbers (or one)"),
    (robot(link("a", collision(BOX)), link("a", collision(BOX))), "2 links are named 'a'"),
    (robot(), "has no <link>"),
]


@pytest.mark.parametrize("text,message", BAD)
def test_bad_urdfs_are_one_line(tmp_path, text, message):
    write(tmp_path, "m.obj", TET_OBJ)
    write(tmp_path, "m.txt", "not a mesh")
    write(tmp_path, "empty.obj", "")
    path = write(tmp_path, "bad.urdf", text)
    part = "a" if "named 'a'" in message else None
    with pytest.raises(InputError) as e:
        load_object(path, part=part)
    assert str(e.value).startswith("bad.urdf: ") and message in str(e.value)
    assert "\n" not in str(e.value)


# ---------------------------------------------------------------- URDFs nobody here wrote

def independent(urdf: Path, link_name: str | None = None):
    """The link's collision meshes read by yourdfpy (origins, scales, file names) and trimesh
    (triangles), placed by the matrices yourdfpy builds: (vertices, triangles, signed volume)."""
    model = yourdfpy.URDF.load(str(urdf), build_scene_graph=False, load_meshes=False,
                               load_collision_meshes=False)
    links = [lk for lk in model.robot.links if lk.collisions
             and (link_name is None or lk.name == link_name)]
    assert len(links) == 1
    points, faces, volume = [], [], 0.0
    for c in links[0].collisions:
        assert c.geometry.mesh is not None
        mesh = trimesh.load(str(urdf.parent / c.geometry.mesh.filename), force="mesh",
                            process=False)
        scale = 1.0 if c.geometry.mesh.scale is None else c.geometry.mesh.scale
        origin = np.eye(4) if c.origin is None else c.origin
        placed = mesh.vertices * scale @ origin[:3, :3].T + origin[:3, 3]
        faces.append(mesh.faces + sum(len(p) for p in points))
        points.append(placed)
        volume += trimesh.Trimesh(placed, mesh.faces, process=False).volume
    return np.concatenate(points), np.concatenate(faces), volume


def test_pybullet_cube_is_its_collision_box():
    obj = load_object(DATA / "cube.urdf")  # visual: cube.obj; collision: <box size="1 1 1"/>
    assert obj.volume == pytest.approx(1.0, rel=1e-12)
    assert np.allclose(obj.bounds, [[-0.5] * 3, [0.5] * 3]) and obj.warnings == ()


@pytest.mark.parametrize("name,part", [("duck_vhacd.urdf", None),
                                       ("mini_cheetah/mini_cheetah.urdf", "abduct_fr")])
def test_pybullet_meshes_with_scale_and_origin(name, part):
    """duck_vhacd: a VHACD decomposition scaled by 0.05 (visual: duck.obj, not read);
    mini_cheetah's abduct_fr: a mesh placed by a turn and a shift, one link of a robot."""
    obj = load_object(DATA / name, part=part)
    points, _, volume = independent(DATA / name, part)
    assert np.allclose(obj.bounds, [points.min(axis=0), points.max(axis=0)], rtol=0,
                       atol=1e-12 * np.ptp(points))
    assert obj.volume == pytest.approx(volume, rel=1e-9)


def test_pybullet_mug_collision_mesh():
    """mug.urdf's collision mesh is mug_col.obj; refused as non-manifold, read with allow_open."""
    with pytest.raises(InputError, match=r"^mug: non-manifold edge") as e:
        load_object(DATA / "objects" / "mug.urdf")
    assert "\n" not in str(e.value)
    obj = load_object(DATA / "objects" / "mug.urdf", allow_open=True)
    points, _, _ = independent(DATA / "objects" / "mug.urdf")
    assert np.allclose(obj.bounds, [points.min(axis=0), points.max(axis=0)], atol=1e-12)
    col = trimesh.load(str(DATA / "objects" / "mug_col.obj"), force="mesh", process=False)
    vis = trimesh.load(str(DATA / "objects" / "mug.obj"), force="mesh", process=False)

    def farthest(a, b):  # the largest distance from a point of a to the nearest point of b
        return np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1)).min(axis=1).max()

    assert farthest(obj.vertices, col.vertices) < 1e-12 < farthest(obj.vertices, vis.vertices)


def test_pybullet_spheres():
    """sphere2.urdf: one sphere of radius 0.5; sphere8cube.urdf: eight of radius 0.1 at the
    corners (±0.4, ±0.4, ±0.4), apart, so the volumes add up."""
    ball = load_object(DATA / "sphere2.urdf")
    true = 4 / 3 * math.pi * 0.5**3
    assert true * (1 - TOL) ** 3 <= ball.volume <= true
    assert np.allclose(ball.bounds, [[-0.5] * 3, [0.5] * 3], atol=1e-12)
    eight = load_object(DATA / "sphere8cube.urdf")
    true = 8 * 4 / 3 * math.pi * 0.1**3
    assert true * (1 - TOL) ** 3 <= eight.volume <= true and eight.shells == 8
    assert np.allclose(eight.bounds, [[-0.5] * 3, [0.5] * 3], atol=1e-12)


def test_pybullet_r2d2_links():
    path = DATA / "r2d2.urdf"
    names = re.findall(r'<link name="([^"]+)"', path.read_text())  # all of them have collision
    with pytest.raises(InputError) as e:
        load_object(path)
    assert str(e.value) == (f"r2d2.urdf: {len(names)} links have collision geometry "
                            f"({', '.join(names)}); name one with part= (--part on the command "
                            "line)")
    body = load_object(path, part="base_link")  # <cylinder length="0.6" radius="0.17"/>
    true = math.pi * 0.17**2 * 0.6
    assert true * (1 - TOL) ** 2 <= body.volume <= true
    assert np.allclose(body.bounds, [[-0.17, -0.17, -0.3], [0.17, 0.17, 0.3]], atol=1e-12)
    # right_leg: <box size="0.6 .2 .1"/> at xyz (0, 0, -0.3), pitch 1.57075 (not quite 90°)
    leg = load_object(path, part="right_leg")
    c, s = math.cos(1.57075), math.sin(1.57075)
    half = np.array([0.3 * c + 0.05 * s, 0.1, 0.3 * s + 0.05 * c])
    shift = np.array([0, 0, -0.3])
    assert np.allclose(leg.bounds, [shift - half, shift + half], atol=1e-12)
    assert leg.volume == pytest.approx(0.6 * 0.2 * 0.1, rel=1e-12)
    with pytest.raises(InputError, match=r"^r2d2\.urdf: no link named 'arm'; .*base_link, "):
        load_object(path, part="arm")


def test_pybullet_blank_lines_before_the_xml_declaration():
    """biped2d_pybullet.urdf starts with blank lines, then <?xml ...?>: strictly not XML, but
    nothing is lost by skipping them (pybullet reads it). Its link r_upperleg is
    <box size="0.05 0.1 .45"/> at xyz (0.018, 0, -0.21715)."""
    path = DATA / "biped" / "biped2d_pybullet.urdf"
    assert path.read_text().startswith("\n")
    obj = load_object(path, part="r_upperleg")
    size, xyz = np.array([0.05, 0.1, 0.45]), np.array([0.018, 0, -0.21715])
    assert obj.volume == pytest.approx(0.05 * 0.1 * 0.45, rel=1e-12)
    assert np.allclose(obj.bounds, [xyz - size / 2, xyz + size / 2], atol=1e-12)


def test_pybullet_package_uri_in_a_sibling_folder():
    """xarm/link1.urdf names package://xarm_description/meshes/...; the package is the
    folder xarm/xarm_description (the old reader stripped the package and missed the file)."""
    path = DATA / "xarm" / "link1.urdf"
    obj = load_object(path)
    mesh = trimesh.load(str(DATA / "xarm" / "xarm_description" / "meshes" / "xarm6" /
                            "collision" / "link1_vhacd.obj"), force="mesh", process=False)
    assert np.allclose(obj.bounds, mesh.bounds, atol=1e-12)
    assert obj.volume == pytest.approx(mesh.volume, rel=1e-9)


RANDOM = [0, 1, 7, 42, 168, 300, 517, 999]


@pytest.mark.parametrize("number", RANDOM)
def test_pybullet_random_urdfs(number):
    path = DATA / "random_urdfs" / f"{number:03d}" / f"{number:03d}.urdf"
    points, faces, volume = independent(path)
    try:
        obj = load_object(path)
    except InputError as e:  # refused only for what the mesh itself is, checked independently
        assert "\n" not in str(e)
        if "is not finite" in str(e):
            assert not np.all(np.isfinite(points))
        else:
            assert "non-manifold edge" in str(e)
            merged = trimesh.Trimesh(points, faces, process=True)  # duplicates merged
            _, counts = np.unique(merged.edges_sorted, axis=0, return_counts=True)
            assert counts.max() > 2
        return
    assert np.allclose(obj.bounds, [points.min(axis=0), points.max(axis=0)], atol=1e-12)
    assert obj.volume == pytest.approx(volume, rel=1e-9)


def test_most_random_urdfs_read():
    read = 0
    for number in RANDOM:
        try:
            load_object(DATA / "random_urdfs" / f"{number:03d}" / f"{number:03d}.urdf")
            read += 1
        except InputError:
            pass
    assert read >= len(RANDOM) - 2


# ---------------------------------------------------------------- the command line

def test_cli_inspect_part(tmp_path, capsys):
    path = write(tmp_path, "two_boxes.urdf", TWO_LINKS)
    assert main(["inspect", str(path), "--part", "boxes", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["volume"] == pytest.approx(9) and info["watertight"]
    assert np.allclose(info["bounds"], [[-4, -1, -1], [2.5, 1, 1]])
    assert main(["inspect", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--part" in err and "boxes, rod" in err
    assert "Traceback" not in err
    assert main(["synthesize", str(path), "--part", "wheel"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no link named 'wheel'" in err


def test_cli_synthesize_part(tmp_path, capsys):
    """synthesize --part rod works on the 0.1 x 0.1 x 3 rod: its size is that box's diagonal,
    and every region lies on the rod's surface."""
    path = write(tmp_path, "two_boxes.urdf", TWO_LINKS)
    assert main(["synthesize", str(path), "--part", "rod", "--contact", "soft", "--json",
                 "--top", "1"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["size"] == pytest.approx(math.sqrt(0.1**2 + 0.1**2 + 3**2), rel=1e-12)
    points = np.array([p for grasp in result["grasps"] for finger in grasp["regions"]
                       for region in finger for p in region["polygon"]])
    half = np.array([0.05, 0.05, 1.5])
    assert len(points) and np.all(np.abs(points) <= half + 1e-12)
    assert np.all(np.isclose(np.abs(points), half, atol=1e-12).any(axis=1))


def test_cli_bad_urdf_one_line(tmp_path, capsys):
    path = write(tmp_path, "bad.urdf", robot(link("a", collision(BOX, xyz="1 2"))))
    assert main(["inspect", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.err == ("forceclosure: error: bad.urdf: link 'a', collision 1: origin xyz "
                            "'1 2' is not three numbers\n")
    assert captured.out == ""
