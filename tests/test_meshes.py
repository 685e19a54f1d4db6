"""kiloloop.meshes: package:// URIs resolve by the ROS/Pinocchio rule or fail naming the package and
the directories searched; meshes load from STL, OBJ and COLLADA; the fitted capsule and box hold
every vertex (a conservative bound); on the UR10 of example-robot-data the planner's capsules
come from the collision meshes and contain every vertex of them."""
import math

import numpy as np
import pytest

import kiloloop as kl
from kiloloop import meshes

from robot_files import erd_robots_dir

trimesh = pytest.importorskip("trimesh")

SEED = 7


def segment_distance(points, p0, p1):
    d = p1 - p0
    L2 = float(d @ d)
    t = np.zeros(len(points)) if L2 == 0.0 else np.clip((points - p0) @ d / L2, 0.0, 1.0)
    return np.linalg.norm(points - (p0 + t[:, None] * d), axis=1)


def test_package_uri_resolves_in_the_first_dir_that_has_it(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    (b / "arm" / "meshes").mkdir(parents=True)
    (b / "arm" / "meshes" / "link.stl").write_text("solid x\nendsolid x\n")
    (a / "arm").mkdir(parents=True)  # the package directory exists here but lacks the file
    got = meshes.resolve_uri("package://arm/meshes/link.stl", tmp_path, [a, b])
    assert got == b / "arm" / "meshes" / "link.stl"
    (a / "arm" / "meshes").mkdir()
    (a / "arm" / "meshes" / "link.stl").write_text("solid y\nendsolid y\n")
    assert meshes.resolve_uri("package://arm/meshes/link.stl", tmp_path, [a, b]) == a / "arm" / "meshes" / "link.stl"


def test_missing_package_names_it_and_the_dirs_searched(tmp_path):
    with pytest.raises(ValueError, match=r"package 'nowhere' not found .*'/opt/x', '/opt/y'"):
        meshes.resolve_uri("package://nowhere/m.stl", tmp_path, ["/opt/x", "/opt/y"])
    with pytest.raises(ValueError, match=r"package 'nowhere' not found .*package_dirs is empty"):
        meshes.resolve_uri("package://nowhere/m.stl", tmp_path, [])


def test_file_and_relative_uris_are_relative_to_the_urdf(tmp_path):
    (tmp_path / "meshes").mkdir()
    f = tmp_path / "meshes" / "m.obj"
    f.write_text("v 0 0 0\n")
    assert meshes.resolve_uri("meshes/m.obj", tmp_path) == f
    assert meshes.resolve_uri("file://meshes/m.obj", tmp_path) == f
    assert meshes.resolve_uri(f"file://{f}", "/elsewhere") == f
    with pytest.raises(ValueError, match=r"'.*meshes/none.obj' not found"):
        meshes.resolve_uri("meshes/none.obj", tmp_path)


@pytest.mark.parametrize("ext", ["stl", "obj", "dae"])
def test_load_mesh_reads_each_format_with_scale(tmp_path, ext):
    if ext == "dae":
        pytest.importorskip("collada")
    box = trimesh.creation.box(extents=(0.2, 0.1, 0.4))
    path = tmp_path / f"box.{ext}"
    box.export(str(path))
    mesh = meshes.load_mesh(path, scale=(2.0, 1.0, 0.5))
    assert np.allclose(mesh.bounds, [[-0.2, -0.05, -0.1], [0.2, 0.05, 0.1]], atol=1e-6)
    center, half = meshes.fit_box(mesh)
    assert np.allclose(center, 0.0, atol=1e-6) and np.allclose(half, [0.2, 0.05, 0.1], atol=1e-6)


def test_collada_unit_is_applied(tmp_path):
    pytest.importorskip("collada")
    path = tmp_path / "box.dae"
    trimesh.creation.box(extents=(1.0, 2.0, 4.0)).export(str(path))
    text = path.read_text()
    path.write_text(text.replace("<asset>", '<asset><unit name="centimeter" meter="0.01"/>', 1))
    mesh = meshes.load_mesh(path)
    assert np.allclose(mesh.extents, [0.01, 0.02, 0.04], atol=1e-9)


def test_fitted_capsule_holds_every_point_and_follows_the_long_axis():
    rng = np.random.default_rng(SEED)
    print(f"seed {SEED}")
    for k in range(30):
        # Random elongated clouds, rotated and shifted.
        pts = rng.normal(size=(400, 3)) * rng.uniform(0.01, 0.3, 3)
        R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        pts = pts @ R.T + rng.uniform(-1, 1, 3)
        p0, p1, r = meshes.fit_capsule(pts)
        assert np.all(segment_distance(pts, p0, p1) <= r), f"seed {SEED} k {k}"
    # A thin rod: the axis is the rod, the radius its thickness.
    rod = trimesh.creation.cylinder(radius=0.02, height=0.5, sections=64)
    p0, p1, r = meshes.fit_capsule(rod)
    assert abs(abs((p1 - p0)[2]) - 0.5) < 0.05 and r < 0.03
    # A single point is a capsule of (almost) zero radius.
    p0, p1, r = meshes.fit_capsule(np.array([[1.0, 2.0, 3.0]]))
    assert r < 1e-9 and np.allclose(p0, [1, 2, 3])


def test_fit_rejects_empty_or_non_finite_points():
    with pytest.raises(ValueError, match="non-empty"):
        meshes.fit_capsule(np.zeros((0, 3)))
    with pytest.raises(ValueError, match="finite"):
        meshes.fit_box(np.array([[0.0, math.nan, 0.0]]))


def test_mesh_collision_without_a_capsule_still_fails_and_with_one_is_used(tmp_path):
    """The C++ side: a mesh needs a supplied capsule (named error otherwise); a supplied one is
    used in place of the mesh, in the link frame."""
    urdf = kl.models_dir() / "ur5" / "ur5.urdf"
    xml = urdf.read_text().replace('<cylinder radius="0.05" length="0.39225"/>',
                                   '<mesh filename="meshes/forearm.stl"/>')
    model = kl.RobotModel.from_urdf(str(urdf))
    with pytest.raises(ValueError, match=r"'forearm_link'.*'mesh'.*no capsule"):
        kl.capsules_from_urdf(xml, model)
    given = {"forearm_link": [(np.array([0.0, 0, 0]), np.array([-0.39, 0, 0]), 0.06)]}
    caps = kl.capsules_from_urdf(xml, model, mesh_capsules=given)
    fore = [c for c in caps if c.link == "forearm_link"]
    assert len(caps) == 7 and len(fore) == 1 and fore[0].radius == 0.06
    with pytest.raises(ValueError, match=r"link 'forarm_link', which is not in the URDF"):
        kl.capsules_from_urdf(xml, model, mesh_capsules={"forarm_link": given["forearm_link"]})


def test_ur10_capsules_hold_every_collision_mesh_vertex():
    robots = erd_robots_dir()
    urdf = robots / "ur_description" / "urdf" / "ur10_robot.urdf"
    package_dirs = [robots.parent.parent]  # package://example-robot-data/robots/... -> share/
    collisions = meshes.mesh_collisions(urdf, package_dirs)
    assert {link for link, *_ in collisions} >= {"base_link", "shoulder_link", "upper_arm_link", "forearm_link",
                                                 "wrist_1_link", "wrist_2_link", "wrist_3_link"}
    caps = meshes.capsules_for_urdf(urdf, package_dirs)
    for link, T, path, scale in collisions:
        v = meshes.load_mesh(path, scale).vertices @ T[:3, :3].T + T[:3, 3]  # in the link frame
        (a, b, r), = caps[link]
        d = segment_distance(v, np.asarray(a), np.asarray(b))
        print(f"{link}: {path.name} {len(v)} vertices, capsule length {np.linalg.norm(b - a):.3f} m "
              f"radius {r:.3f} m, largest vertex distance {d.max():.4f} m")
        assert np.all(d <= r), f"{link}: a vertex is {d.max() - r:.3g} m outside its capsule"
        assert r < 0.15  # a bound, but not a uselessly loose one (UR10 links are < 0.1 m in radius)
    # The planner's capsules: chain links from the fitted meshes, ee_link's box folded onto wrist_3.
    model = kl.RobotModel.from_urdf(str(urdf), root="base_link", tip="tool0")
    with pytest.raises(ValueError, match=r"link 'base_link': collision geometry 'mesh'.*base.stl"):
        kl.capsules_from_urdf(str(urdf), model)
    planner = kl.capsules_from_urdf(str(urdf), model, mesh_capsules=caps)
    assert [c.link for c in planner].count("wrist_3_link") == 2
    assert len(planner) == 8
