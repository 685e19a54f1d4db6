"""kl.capsules_from_urdf: a collision geometry that cannot be bounded by a capsule (a mesh) is an
error naming the link, not a link silently missing from the planner's collision model."""
import re

import pytest

import kiloloop as kl


def test_mesh_collision_raises_naming_the_link_and_geometry():
    urdf = kl.models_dir() / "ur5" / "ur5.urdf"
    model = kl.RobotModel.from_urdf(str(urdf))
    xml = urdf.read_text()
    assert len(kl.capsules_from_urdf(xml, model)) == 7  # every chain link has a cylinder
    # The forearm's cylinder becomes a mesh.
    meshed, n = re.subn(r'<cylinder radius="0.05" length="0.39225"/>', '<mesh filename="forearm.stl"/>', xml)
    assert n == 1
    with pytest.raises(ValueError, match=r"'forearm_link'.*'mesh'"):
        kl.capsules_from_urdf(meshed, model)
