"""Terrains (sil/terrain.py) on the floating-base plant: the heights a scenario judges footholds
with are the ones MuJoCo collides with, the seed fixes the terrain, and the compliant ground's
normal stiffness really is the N/m asked for (static sinkage of known loads)."""
from pathlib import Path

import mujoco
import numpy as np
import pytest

from kiloloop.sil.floating_plant import FloatingBasePlant
from kiloloop.sil.terrain import Compliant, Rough, Stones

BALL_RADIUS = 0.05  # [m]


def ball_urdf(directory: Path, mass: float) -> Path:
    """A free sphere: the simplest body with a known load on the ground (its weight)."""
    path = Path(directory) / f"ball_{mass:g}.urdf"
    path.write_text(
        f'<?xml version="1.0"?>\n<robot name="ball"><link name="ball"><inertial><mass value="{mass}"/>'
        '<inertia ixx="0.002" iyy="0.002" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial>'
        f'<collision><geometry><sphere radius="{BALL_RADIUS}"/></geometry></collision></link></robot>\n')
    return path


def ball_plant(tmp_path, mass, terrain, cone="elliptic"):
    return FloatingBasePlant(ball_urdf(tmp_path, mass), {"feet": {"bodies": ["ball"]},
                                                         "physics": {"cone": cone}},
                             terrain=terrain)


def ray_height(plant, x, y) -> float:
    """Height of the ground geoms under (x, y), by a downward ray (MuJoCo's own geometry; the
    robot's body excluded)."""
    geomid = np.zeros(1, dtype=np.int32)
    top = 1.0
    dist = mujoco.mj_ray(plant.model, plant.data, np.array([x, y, top]), np.array([0.0, 0.0, -1.0]),
                         None, 1, plant.model.body(plant.base_body).id, geomid)
    return top - dist


@pytest.mark.parametrize("mass", [2.0, 8.0])
def test_compliant_ground_sinks_by_weight_over_stiffness(tmp_path, mass):
    k = 1e3  # [N/m], the figure
    plant = ball_plant(tmp_path, mass, Compliant(stiffness=k, load_mass=mass))
    plant.step(3000)  # 3 s: critically damped at sqrt(k/m) >= 11 rad/s, settled
    force = plant.foot_contact_forces()[0, 2]
    sinkage = BALL_RADIUS - plant.foot_positions()[0, 2]
    assert force == pytest.approx(mass * 9.81, rel=1e-3)
    assert force / sinkage == pytest.approx(k, rel=0.02)


def test_compliant_ground_refuses_the_pyramidal_cone(tmp_path):
    with pytest.raises(ValueError, match="elliptic"):
        ball_plant(tmp_path, 2.0, Compliant(), cone="pyramidal")


def test_stone_heights_are_the_ones_mujoco_collides_with(tmp_path):
    stones = Stones(spread=0.03, seed=3, gap=0.05)
    plant = ball_plant(tmp_path, 1.0, stones)
    rng = np.random.default_rng(0)
    for x, y in rng.uniform([-0.3, -1.2], [3.0, 1.2], size=(200, 2)):
        assert stones.height(x, y) == pytest.approx(ray_height(plant, x, y), abs=1e-9)
    assert stones.height(0.0, 0.0) == 0.0  # the start pad
    assert np.ptp(stones.tops) > 0.03  # heights really spread (uniform in +-0.03 m)
    assert stones.height(stones.pad + stones.size + 0.5 * stones.gap, 0.0) == stones.base_z


def test_rough_heights_match_the_heightfield(tmp_path):
    rough = Rough(amplitude=0.02, bump_length=0.3, seed=5)
    plant = ball_plant(tmp_path, 1.0, rough)
    rng = np.random.default_rng(1)
    errors = [rough.height(x, y) - ray_height(plant, x, y)
              for x, y in rng.uniform([1.0, -1.0], [6.0, 1.0], size=(200, 2))]
    # Bilinear against MuJoCo's two triangles per 2 cm cell: far below the 2 cm amplitude.
    assert np.max(np.abs(errors)) < 1e-3
    assert np.abs(rough.heights).max() == pytest.approx(0.02)
    assert rough.height(0.0, 0.3) == 0.0  # flat start


def test_terrains_are_seeded():
    assert np.array_equal(Stones(spread=0.02, seed=1).tops, Stones(spread=0.02, seed=1).tops)
    assert not np.array_equal(Stones(spread=0.02, seed=1).tops, Stones(spread=0.02, seed=2).tops)
    assert np.array_equal(Rough(0.02, 0.3, seed=4).heights, Rough(0.02, 0.3, seed=4).heights)


def test_terrain_and_slope_do_not_mix(tmp_path):
    with pytest.raises(ValueError, match="slope"):
        FloatingBasePlant(ball_urdf(tmp_path, 1.0), {"feet": {"bodies": ["ball"]}}, slope_deg=5.0,
                          terrain=Stones(spread=0.01))
