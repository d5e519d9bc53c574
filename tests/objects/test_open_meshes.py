"""Open meshes: oriented outward, described by inspect, grasped with --allow-open.

Ground truth: a cube with a face removed (every normal points away from the centre),
pybullet_data's mug (its file, read by trimesh; its outside found by rays cast from far
away, not by the winding-number rule the library uses), and the CLI's exit statuses.
"""

from __future__ import annotations

import json
import os

import numpy as np
import pybullet_data
import pytest
import shapely
import trimesh
from test_outer_surface import distance_to_triangles, original_pieces, winding_number

from forceclosure.app.cli import main
from forceclosure.datasets import Job, process_object
from forceclosure.datasets.records import check_job
from forceclosure.errors import InputError
from forceclosure.objects import Polyhedron
from forceclosure.objects.io import load_object
from forceclosure.synthesis.best import synthesize

DATA = pybullet_data.getDataPath()
MUG = os.path.join(DATA, "objects", "mug.obj")


def _open_cube():
    box = trimesh.creation.box(extents=[2, 2, 2])  # centred on the origin, facing out
    top = np.flatnonzero(box.triangles[:, :, 2].min(axis=1) > 0.99)
    return box.vertices, np.delete(box.faces, top, axis=0)


@pytest.mark.parametrize("how", ["as given", "inside out", "mixed"])
def test_a_cube_without_its_lid_faces_out(how):
    V, T = _open_cube()
    if how == "inside out":
        T = T[:, ::-1]
    if how == "mixed":
        T = T.copy()
        T[::3] = T[::3, ::-1]
    cup = Polyhedron.from_arrays(V, T, allow_open=True)
    assert (cup.watertight, cup.holes, cup.boundary_edges, cup.defects) == (False, 1, 4,
                                                                             ("open",))
    assert len(cup.faces) == 5
    for f in cup.faces:  # closed form: each side's normal is its centre's direction
        centre = cup.vertices[np.unique(cup.triangles[f.triangles])].mean(axis=0)
        np.testing.assert_allclose(f.normal, np.round(centre), atol=1e-12)
    if how == "inside out":
        assert any("flipped" in w for w in cup.warnings)
    if how == "mixed":
        assert any("re-oriented" in w for w in cup.warnings)
    with pytest.raises(InputError, match=r"allow_open=True \(--allow-open on the command"):
        Polyhedron.from_arrays(V, T)


def test_a_flat_sheet_has_no_inside_and_says_so():
    sheet = Polyhedron.from_arrays([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]],
                                   [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
                                   allow_open=True)
    assert sheet.faces[0].normal.tolist() == [0, 0, 1]  # the file's winding, kept
    assert any("no inside" in w for w in sheet.warnings)


def _outward_by_rays(mesh, rays=400, seed=0):
    """Cast rays from far away at the mesh: (triangle hit first, ray direction) pairs. A
    triangle hit first from outside is seen from its outside."""
    rng = np.random.default_rng(seed)
    centre = mesh.bounds.mean(axis=0)
    size = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0)))
    target = mesh.bounds[0] + rng.random((rays, 3)) * np.ptp(mesh.bounds, axis=0)
    d = rng.normal(size=(rays, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    origins = centre + 2 * size * d
    direction = target - origins
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    caster = trimesh.ray.ray_triangle.RayMeshIntersector(mesh)  # double precision
    locations, index_ray, index_tri = caster.intersects_location(origins, direction,
                                                                 multiple_hits=True)
    first = {}
    for loc, r, t in zip(locations, index_ray, index_tri, strict=True):
        dist = np.linalg.norm(loc - origins[r])
        if r not in first or dist < first[r][0]:
            first[r] = (dist, t)
    return [(t, direction[r]) for r, (_, t) in first.items()]


def test_the_mug_faces_out_where_rays_from_outside_meet_it():
    mug = load_object(MUG, allow_open=True)
    hits = _outward_by_rays(mug.to_trimesh())
    assert len(hits) > 300
    normals = np.array([mug.faces[mug.face_of_triangle[t]].normal for t, _ in hits])
    assert np.all(np.einsum("ij,ij->i", normals, [d for _, d in hits]) < 0)


def _mug_pieces_oriented_by_rays():
    """The file's cup (closed: by its volume) and handle (open: by the rays that meet it
    first from outside)."""
    mesh, pieces = original_pieces(MUG)
    handle = next(p for p in pieces if not p.is_watertight)
    trimesh.repair.fix_winding(handle)
    votes = [np.dot(handle.face_normals[t], d) for t, d in _outward_by_rays(handle)]
    # rays through the open ends meet the tube from inside: a clear majority decides
    assert len(votes) > 100 and abs(np.mean(np.sign(votes))) > 0.5
    if np.mean(np.sign(votes)) > 0:
        handle.invert()
    return mesh, [p for p in pieces if p.is_watertight] + [handle]


def check_mug_regions(found, samples=1500):
    """Each region point lies on the mug file's triangles; a step out along its normal is
    outside the cup and the handle, a step in is inside one of them."""
    mesh, pieces = _mug_pieces_oriented_by_rays()
    size = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0)))
    eps = 1e-6 * size
    for r in found:
        points, normals = r.sample(samples, seed=2)
        p, n = points.reshape(-1, 3), normals.reshape(-1, 3)
        assert max(distance_to_triangles(q, mesh.triangles).min() for q in p) <= 1e-9 * size
        deepest = np.zeros(len(p))
        for piece in pieces:
            assert np.all(winding_number(piece.vertices, piece.faces, p + eps * n) < 0.5)
            deepest = np.maximum(deepest, winding_number(piece.vertices, piece.faces,
                                                         p - eps * n))
        assert np.all(deepest > 0.5)


@pytest.mark.parametrize("args", [
    pytest.param(["--fingers", "3", "--contact", "hard"], marks=pytest.mark.long),  # 10 s
    pytest.param(["--fingers", "2", "--contact", "soft"], marks=pytest.mark.long)])
def test_the_mug_is_grasped_from_the_command_line(capsys, args):
    assert main(["synthesize", MUG, *args, "--mu", "0.5"]) == 2
    assert "--allow-open" in capsys.readouterr().err
    assert main(["synthesize", MUG, "--allow-open", *args, "--mu", "0.5", "--top", "2",
                 "--samples", "4000", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert len(record["grasps"]) == 2
    assert all(g["certificate"]["holds"] for g in record["grasps"])
    fingers, contact = int(args[1]), args[3]
    result = synthesize(MUG, fingers, contact, 0.5, top=2, samples=4000, allow_open=True)
    assert [r.to_dict()["faces"] for r in result.found] == [g["faces"]
                                                            for g in record["grasps"]]
    check_mug_regions(result.found)


def test_synthesize_takes_what_load_object_takes():
    box = trimesh.creation.box(extents=[2, 1, 1])
    s = synthesize(box, 2, "soft", 0.5, top=1)
    assert s.method == "faces" and s.found[0].certify().holds
    assert synthesize(shapely.box(0, 0, 2, 1), 2, "hard", 0.5, top=1).found[0].certify().holds
    assert synthesize("cube", 2, "soft", 0.5, top=1).found[0].certify().holds  # bundled name
    opened = trimesh.Trimesh(*_open_cube(), process=False)
    with pytest.raises(InputError, match="allow_open=True"):
        synthesize(opened, 3, "hard", 0.5)
    assert synthesize(opened, 3, "hard", 0.5, top=1, samples=3000,
                      allow_open=True).found[0].certify().holds
    back = Polyhedron.from_trimesh(load_object("l-prism").to_trimesh())
    assert back.volume == pytest.approx(load_object("l-prism").volume, rel=1e-12)


def test_dataset_jobs_opt_in(tmp_path):
    refused = process_object(MUG, Job(contact="soft", mu=0.5, top=1, samples=2000))
    assert refused["status"] == "failed" and "allow_open" in refused["error"]
    done = process_object(MUG, Job(contact="soft", mu=0.5, top=1, samples=2000,
                                   allow_open=True))
    assert done["status"] == "done" and done["grasps"][0]["certificate"]["holds"]
    assert Job(allow_open=True).identity()["allow_open"] is True
    # a results folder written before the option existed resumes with allow_open off
    old = Job().identity()
    del old["allow_open"]
    (tmp_path / "job.json").write_text(json.dumps(old))
    check_job(tmp_path, Job())
    with pytest.raises(InputError, match="allow_open False there, True here"):
        check_job(tmp_path, Job(allow_open=True))
    out = tmp_path / "run"
    assert main(["dataset", MUG, "--out", str(out), "--allow-open", "--contact", "soft",
                 "--mu", "0.5", "--top", "1", "--samples", "2000", "--workers", "1"]) == 0
    assert json.loads((out / "job.json").read_text())["allow_open"] is True


def test_two_solids_glued_at_an_edge_each_face_out():
    """tests/data/bad_objects/non_manifold.obj: two tetrahedra sharing one edge (shared by
    four triangles), the second given inside out. Each is turned out on its own: every
    triangle's normal points away from its own tetrahedron's centre (closed form)."""
    path = os.path.join(os.path.dirname(os.path.dirname(__file__)), "data", "bad_objects",
                        "non_manifold.obj")
    poly = load_object(path, allow_open=True)
    assert poly.defects == ("non-manifold",) and poly.non_manifold_edges == 1
    V, T = poly.vertices, poly.triangles
    upper = np.any(V[T][:, :, 1] > 0.5, axis=1) | np.any(V[T][:, :, 2] > 0.5, axis=1)
    for group in (upper, ~upper):
        centre = V[np.unique(T[group])].mean(axis=0)
        normals = np.cross(V[T[group, 1]] - V[T[group, 0]], V[T[group, 2]] - V[T[group, 0]])
        assert group.sum() == 4
        assert np.all(np.einsum("ij,ij->i", normals, V[T[group]].mean(axis=1) - centre) > 0)
