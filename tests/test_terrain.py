"""Terrains (sil/terrain.py) on the floating-base plant: the heights a scenario judges footholds
with are the ones MuJoCo collides with, the seed fixes the terrain, and the compliant ground's
normal stiffness really is the N/m asked for (static sinkage of known loads)."""
from pathlib import Path

import mujoco
import numpy as np
import pytest

from kiloloop.sil.floating_plant import DEFAULT_PHYSICS, FloatingBasePlant, set_friction_options
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


# --- The heightfield's contact (cpp/sil/smooth_heightfield.hpp) --------------------------------

def sphere_world(ground, solref=(0.008, 1.0)):
    """A 20 mm, 0.3 kg sphere (a quadruped's foot) above `ground`: "plane", or a Rough terrain
    spec; the quadruped plant's physics options."""
    spec = mujoco.MjSpec()
    set_friction_options(spec, DEFAULT_PHYSICS)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.timestep = DEFAULT_PHYSICS["timestep"]
    if ground == "plane":
        geom = spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05])
        geom.friction = [0.8, 0.005, 0.0001]
        geom.solref, geom.solmix = list(solref), 1e3  # as Rough sets its own
    else:
        ground.add_to(spec, 0.8)
    body = spec.worldbody.add_body(name="foot", pos=[1.2, 0.15, 0.1])
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.02, 0, 0], mass=0.3)
    model = spec.compile()
    return model, mujoco.MjData(model)


def drop(model, data, vz, steps=150):
    """The sphere's height [m] each step after it is thrown down at vz [m/s] (0.5 m/s forward),
    and the largest number of contacts it had at once."""
    data.qpos[:3] = [1.2, 0.15, 0.021]
    data.qvel[0], data.qvel[2] = 0.5, vz
    z, most = [], 0
    for _ in range(steps):
        mujoco.mj_step(model, data)
        z.append(data.qpos[2])
        most = max(most, data.ncon)
    return np.array(z), most


@pytest.mark.parametrize("vz", [-1.0, -3.0])
def test_a_flat_heightfield_is_the_plane_to_a_foot(vz):
    """One contact per sphere, the plane's: the same motion as on MuJoCo's plane with the same
    contact parameters, also for a foot landing at 3 m/s, which sinks more than its radius' worth
    of the 2 cm cells and which MuJoCo's prism collider held down (scripts/hfield_trap_probe.py)."""
    z_plane, n_plane = drop(*sphere_world("plane"), vz)
    z_field, n_field = drop(*sphere_world(Rough(amplitude=0.0, bump_length=0.3)), vz)
    assert n_plane == n_field == 1
    np.testing.assert_allclose(z_field, z_plane, rtol=0, atol=1e-12)  # round-off: 1e-16 m measured
    assert z_field[-1] == pytest.approx(0.02, abs=1e-3)  # released: resting on the surface


def test_the_stock_collider_is_kept_for_unmarked_heightfields():
    """Rough(smooth_contact=False) keeps MuJoCo's prism collider: more than one contact for one
    sphere, and with MuJoCo's default contact time constant (0.02 s) a foot landing at 3 m/s
    stays held below the surface, where the smooth contact releases it."""
    def rest(smooth):
        rough = Rough(amplitude=0.0, bump_length=0.3, contact_time_constant=0.02, smooth_contact=smooth)
        return drop(*sphere_world(rough), -3.0)
    z_stock, most_stock = rest(False)
    z_smooth, most_smooth = rest(True)
    assert most_stock > 1 and most_smooth == 1
    assert z_stock[-1] < 0.02 - 0.01                         # held 10+ mm deep
    assert z_smooth[-1] == pytest.approx(0.02, abs=1e-3)     # on the surface


def test_the_contact_follows_the_surface_slope():
    """sphere_on_bilinear on a plane tilted along x (heights linear in the column): the normal is
    the plane's, dist the sphere's distance from it; off the grid there is no contact."""
    from kiloloop.sil import native

    nrow, ncol, rx, ry = 5, 9, 0.4, 0.2            # cells 0.1 m
    slope = 0.25                                    # [m/m] along x
    xs = np.linspace(-rx, rx, ncol)
    heights = np.tile(slope * (xs + rx), (nrow, 1)) / (2 * slope * rx)  # normalized 0..1
    elevation = 2 * slope * rx
    centre = np.array([0.05, 0.03, 0.3])
    dist, pos, normal = native.sphere_on_bilinear(heights, rx, ry, elevation, centre, 0.02, 1.0)
    n = np.array([-slope, 0.0, 1.0]) / np.hypot(slope, 1.0)
    np.testing.assert_allclose(normal, n, atol=1e-12)
    surface = slope * (centre[0] + rx)
    assert dist == pytest.approx((centre[2] - surface) * n[2] - 0.02, abs=1e-12)
    np.testing.assert_allclose(pos, centre - (0.02 + 0.5 * dist) * n, atol=1e-12)
    assert native.sphere_on_bilinear(heights, rx, ry, elevation, np.array([0.5, 0.0, 0.0]), 0.02) is None
    assert native.sphere_on_bilinear(heights, rx, ry, elevation, centre, 0.02, margin=0.0) is None
