"""The quadruped's foot radius from the foot link's collision geometry (robot/foot_geometry.py):
how far it reaches below the link's origin along the trunk's down direction, for the placements
real descriptions use (sphere about the origin, offset sphere, mesh, shank cylinder beside the
sphere, a foot frame turned by the fixed joints), and on example-robot-data's Go2, whose foot is a
mesh: it stands at the derived height. foot_contact: the contact sphere itself (centre in the
foot link's frame and radius) when the lowest geometry is a sphere, else one about the origin."""
from pathlib import Path

import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.robot.foot_geometry import foot_contact, foot_depth

from kiloloop.bench.quadruped_robots import robot_file


def _urdf(tmp_path: Path, collisions: str, ankle_rpy: str = "0 0 0") -> Path:
    """trunk -> (revolute) shank -> (fixed, ankle_rpy) foot, the foot link with `collisions`."""
    text = f"""<robot name="leg">
  <link name="trunk"/>
  <link name="shank"/>
  <link name="foot">{collisions}</link>
  <joint name="knee" type="revolute"><parent link="trunk"/><child link="shank"/>
    <origin xyz="0 0 -0.1"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="10"/></joint>
  <joint name="ankle" type="fixed"><parent link="shank"/><child link="foot"/>
    <origin xyz="0 0 -0.2" rpy="{ankle_rpy}"/></joint>
</robot>"""
    path = tmp_path / "leg.urdf"
    path.write_text(text)
    return path


def _collision(geometry: str, xyz: str = "0 0 0", rpy: str = "0 0 0") -> str:
    return f'<collision><origin xyz="{xyz}" rpy="{rpy}"/><geometry>{geometry}</geometry></collision>'


def test_sphere_about_the_origin_is_its_radius(tmp_path):
    path = _urdf(tmp_path, _collision('<sphere radius="0.02"/>'))
    assert foot_depth(path, "foot", "trunk") == pytest.approx(0.02, abs=1e-15)


def test_offset_sphere_reaches_its_radius_minus_its_height(tmp_path):
    # ANYmal B's placement: radius 0.031 m, centre 0.02325 m up the shank.
    path = _urdf(tmp_path, _collision('<sphere radius="0.031"/>', xyz="0 0 0.02325"))
    assert foot_depth(path, "foot", "trunk") == pytest.approx(0.00775, abs=1e-12)


def test_the_lowest_of_several_geometries_counts(tmp_path):
    # ANYmal C's foot link also carries a shank cylinder above the contact sphere.
    both = (_collision('<cylinder radius="0.0175" length="0.2825"/>', xyz="0 0 0.169") +
            _collision('<sphere radius="0.03"/>', xyz="0 0 0.0225"))
    assert foot_depth(_urdf(tmp_path, both), "foot", "trunk") == pytest.approx(0.0075, abs=1e-12)


def test_a_turned_foot_frame_is_measured_along_the_trunks_down(tmp_path):
    # The ankle turns the foot frame 90 deg about y: the trunk's down is the foot frame's +x, and
    # a box 0.01 x 0.04 x 0.06 reaches half its x side below the origin, not half its z side.
    box = _collision('<box size="0.01 0.04 0.06"/>')
    path = _urdf(tmp_path, box, ankle_rpy=f"0 {np.pi / 2} 0")
    assert foot_depth(path, "foot", "trunk") == pytest.approx(0.005, abs=1e-12)
    assert foot_depth(_urdf(tmp_path, box), "foot", "trunk") == pytest.approx(0.03, abs=1e-12)


def test_a_mesh_reaches_its_lowest_vertex(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.016)
    sphere.apply_translation([0.0, 0.0, 0.004])
    sphere.export(tmp_path / "foot.stl")
    lowest = -float(sphere.vertices[:, 2].min())
    path = _urdf(tmp_path, _collision('<mesh filename="foot.stl" scale="1 1 1"/>'))
    assert foot_depth(path, "foot", "trunk") == pytest.approx(lowest, abs=1e-9)
    assert 0.0115 < lowest < 0.0121


def test_contact_of_an_offset_sphere_is_its_centre_and_radius(tmp_path):
    # ANYmal C's foot link: the shank cylinder above, the contact sphere 22.5 mm up the shank.
    both = (_collision('<cylinder radius="0.0175" length="0.2825"/>', xyz="0 0 0.169") +
            _collision('<sphere radius="0.03"/>', xyz="0.001 -0.002 0.0225", rpy="0.3 0 0"))
    offset, radius = foot_contact(_urdf(tmp_path, both), "foot", "trunk")
    np.testing.assert_array_equal(offset, [0.001, -0.002, 0.0225])
    assert radius == 0.03


def test_contact_of_a_sphere_about_the_origin_is_exactly_its_depth(tmp_path):
    path = _urdf(tmp_path, _collision('<sphere radius="0.0213"/>'))
    offset, radius = foot_contact(path, "foot", "trunk")
    assert offset.shape == (3,) and not offset.any()
    assert radius == foot_depth(path, "foot", "trunk") == 0.0213


def test_contact_of_a_mesh_or_no_geometry_is_about_the_origin(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.016)
    sphere.apply_translation([0.0, 0.0, 0.004])  # a mesh sphere off the origin: still offset 0
    sphere.export(tmp_path / "foot.stl")
    path = _urdf(tmp_path, _collision('<mesh filename="foot.stl" scale="1 1 1"/>'))
    offset, radius = foot_contact(path, "foot", "trunk")
    assert not offset.any()
    assert radius == foot_depth(path, "foot", "trunk") == pytest.approx(-sphere.vertices[:, 2].min(), abs=1e-9)
    offset, radius = foot_contact(_urdf(tmp_path, ""), "foot", "trunk")
    assert not offset.any() and radius == 0.0


def test_anymal_b_gets_its_offset_sphere(tmp_path):
    path = robot_file("anymal_b", tmp_path)
    if path is None:
        pytest.skip("example-robot-data not installed")
    from kiloloop.robot.quadruped import controller_config
    config = controller_config(kl.Robot.load(path))
    assert config.foot_radius == pytest.approx(0.031, abs=1e-6)
    np.testing.assert_allclose(config.foot_offset, [0.0, 0.0, 0.02325], atol=1e-6)


def test_no_collision_is_a_point_foot(tmp_path):
    assert foot_depth(_urdf(tmp_path, ""), "foot", "trunk") == 0.0


def test_go2s_mesh_foot_stands_at_the_derived_height(tmp_path):
    path = robot_file("go2", tmp_path)
    if path is None:
        pytest.skip("example-robot-data not installed")
    robot = kl.Robot.load(path)
    # Before: 0 (a mesh was not read), and Go2 stood 23 mm above the height it derived.
    from kiloloop.robot.quadruped import controller_config
    assert 0.015 < controller_config(robot).foot_radius < 0.03
    result = scenarios.run_named("quadruped-stand", robot, seed=0, duration=2.0)
    c = result.criteria["height_error_after_1s_m"]
    assert c["passed"], f"height error {c['value']} (needs {c['op']} {c['threshold']})"
