"""Terrains for the floating-base plant: a terrain spec -> MuJoCo geoms on an MjSpec, seeded, plus
the ground height under any point so that scenarios can judge where the feet landed.

Every terrain is flat at z = 0 for x < `pad` [m] (Compliant: everywhere), where the plant puts the
robot standing over the origin (FloatingBasePlant._stand_pos assumes flat ground at z = 0), and has
a base plane below everything (nothing falls out of the world). Units SI, heights along world z;
the rough and stony part runs along +x, the direction the scenarios trot.

  Stones     square stones (boxes, side `size`) on a grid, tops at random heights, seeded;
             `gap` [m] between neighbours, the base plane `depth` below the lowest top.
  Rough      a heightfield of smooth random bumps (peak |height| `amplitude`, correlation length
             `bump_length`), seeded; one contact per foot sphere (kiloloop's collider).
  Compliant  a flat floor whose normal stiffness per contact is `stiffness` [N/m] (MuJoCo's soft
             contact calibrated with each robot geom's constraint mass; see configure).
"""
from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from ..errors import InputError

_SPIN_ROLL = (0.005, 0.0001)  # MuJoCo's default torsional and rolling friction (as the plant's floor)
BASE = "terrain_base"


def _geom_flags(geom, friction: float) -> None:
    # Ground geoms: contype 1, conaffinity 0 (they hit the robot, conaffinity 1, never each other).
    geom.contype, geom.conaffinity = 1, 0
    geom.friction = [friction, *_SPIN_ROLL]


def _add_plane(spec, name: str, z: float, friction: float):
    geom = spec.worldbody.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_PLANE,
                                   size=[0.0, 0.0, 0.05], pos=[0.0, 0.0, z])
    _geom_flags(geom, friction)
    return geom


@dataclass(frozen=True)
class Stones:
    """Stepping stones: square boxes of side `size` [m] with `gap` [m] between them, tops uniform
    in [-spread, +spread] [m] (seeded), over x in [pad, length], |y| <= half_width; the start pad
    (x < pad) is one flat stone at z = 0. A foot that misses every stone lands on the base plane
    `depth` [m] below the lowest top."""
    spread: float
    seed: int = 0
    size: float = 0.3
    gap: float = 0.0
    pad: float = 0.4
    length: float = 8.0
    half_width: float = 1.5
    depth: float = 0.1

    def __post_init__(self):
        pitch = self.size + self.gap
        nx = int(np.ceil((self.length - self.pad) / pitch))
        ny = int(np.ceil(2 * self.half_width / pitch))
        rng = np.random.default_rng(self.seed)
        object.__setattr__(self, "tops", rng.uniform(-self.spread, self.spread, size=(nx, ny)))
        object.__setattr__(self, "_pitch", pitch)
        object.__setattr__(self, "_y0", -0.5 * ny * pitch)

    @property
    def base_z(self) -> float:
        return min(0.0, float(self.tops.min())) - self.depth

    def add_to(self, spec, friction: float) -> None:
        _add_plane(spec, BASE, self.base_z, friction)
        h = 0.5 * self.size
        bottom = self.base_z
        # Start pad: from x = -pad back, as wide as the stone field, top at 0.
        pad_half = np.array([self.pad + 1.0, 0.5 * self.tops.shape[1] * self._pitch, -0.5 * bottom])
        geom = spec.worldbody.add_geom(name="stone_pad", type=mujoco.mjtGeom.mjGEOM_BOX,
                                       size=pad_half, pos=[self.pad - pad_half[0], 0.0, 0.5 * bottom])
        _geom_flags(geom, friction)
        for (i, j), top in np.ndenumerate(self.tops):
            cx, cy = self._centre(i, j)
            half_z = 0.5 * (top - bottom)
            geom = spec.worldbody.add_geom(name=f"stone_{i}_{j}", type=mujoco.mjtGeom.mjGEOM_BOX,
                                           size=[h, h, half_z], pos=[cx, cy, bottom + half_z])
            _geom_flags(geom, friction)

    def _centre(self, i: int, j: int) -> tuple[float, float]:
        # Cell i spans [pad + i pitch, pad + (i + 1) pitch]; its stone is centred in it, so the
        # pad's edge has half a gap too.
        return self.pad + (i + 0.5) * self._pitch, self._y0 + (j + 0.5) * self._pitch

    def stone_at(self, x: float, y: float) -> tuple[int, int] | None:
        """Grid index of the stone whose top contains (x, y), None for the pad, a gap or outside."""
        i, j = int(np.floor((x - self.pad) / self._pitch)), int(np.floor((y - self._y0) / self._pitch))
        if not (0 <= i < self.tops.shape[0] and 0 <= j < self.tops.shape[1]):
            return None
        cx, cy = self._centre(i, j)
        if abs(x - cx) > 0.5 * self.size or abs(y - cy) > 0.5 * self.size:
            return None
        return i, j

    def height(self, x: float, y: float) -> float:
        """Ground height [m] under (x, y): the pad, a stone's top, or the base plane in a gap."""
        if x < self.pad and abs(y) <= 0.5 * self.tops.shape[1] * self._pitch:
            return 0.0
        ij = self.stone_at(x, y)
        return self.base_z if ij is None else float(self.tops[ij])

    def configure(self, model, robot_geoms) -> None:
        pass


@dataclass(frozen=True)
class Rough:
    """Heightfield of smooth random bumps: white noise (seeded) low-passed with a Gaussian of
    standard deviation bump_length / 4, scaled so that the largest |height| is `amplitude` [m];
    faded in over x in [pad, 2 pad] so the start is flat. Covers x in [-pad, length],
    |y| <= half_width on a grid of `cell` [m].

    Its contact is kiloloop's (cpp/sil/smooth_heightfield.hpp, `smooth_contact`): one contact per
    foot sphere, on the plane tangent to the bilinear surface below its centre (the surface
    `height` describes), where MuJoCo's heightfield collider makes one per triangular prism
    touched: 4-16 contacts for one 20 mm sphere on the 2 cm cells, whose side faces meet a foot
    sunk below a cell's surface and hold it (normals up to 90 deg from vertical; a foot landing at
    2-3 m/s stayed 17-27 mm deep, `python scripts/hfield_trap_probe.py`). Go1 at 35 ms of
    actuation delay fell on seeds 0-4 on a FLAT heightfield of MuJoCo's, while it trots on the
    plane; with this contact a flat heightfield is the plane to round-off (1e-16 m,
    tests/test_terrain.py) and Go1 passes seeds 0-4 at 35 ms. Foot shapes other than spheres
    keep MuJoCo's collider.

    The contact is stiffer than MuJoCo's default (solref time constant `contact_time_constant`
    instead of 0.02 s; the heightfield's solmix makes it the pair's): ground a foot landing at
    2-3 m/s sinks 14-22 mm into (the plane's figures at 0.02 s) is not rigid; at 0.008 s (8
    physics steps at 1 ms) 5-8 mm. Measured at 35 ms with 0.02 s instead: our model passes seeds
    0-4, Go1 falls on seeds 1 and 2 (bench/go1_35ms_diagnosis.md). At 10 ms both robots pass
    seeds 0-4 either way."""
    amplitude: float
    bump_length: float
    seed: int = 0
    cell: float = 0.02
    pad: float = 0.4
    length: float = 8.0
    half_width: float = 1.5
    contact_time_constant: float = 0.008  # [s] solref[0] (damping ratio 1)
    # One contact per foot sphere from the bilinear surface (cpp/sil/smooth_heightfield.hpp)
    # instead of MuJoCo's one per heightfield prism touched; other foot shapes keep MuJoCo's.
    smooth_contact: bool = True

    def __post_init__(self):
        x = np.arange(-self.pad, self.length + 0.5 * self.cell, self.cell)
        y = np.arange(-self.half_width, self.half_width + 0.5 * self.cell, self.cell)
        rng = np.random.default_rng(self.seed)
        noise = rng.standard_normal((y.size, x.size))
        # Gaussian low-pass in the frequency domain (periodic, fine for a random field).
        sigma = 0.25 * self.bump_length / self.cell  # [cells]
        fy, fx = np.fft.fftfreq(y.size)[:, None], np.fft.fftfreq(x.size)[None, :]
        gain = np.exp(-2.0 * (np.pi * sigma) ** 2 * (fx ** 2 + fy ** 2))
        h = np.real(np.fft.ifft2(np.fft.fft2(noise) * gain))
        fade = np.clip((x - self.pad) / self.pad, 0.0, 1.0)[None, :]
        h = h * fade
        h *= self.amplitude / max(np.abs(h).max(), 1e-12)
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "heights", h)  # (rows along y, columns along x) [m]

    @property
    def base_z(self) -> float:
        return float(self.heights.min()) - 0.05

    def add_to(self, spec, friction: float) -> None:
        _add_plane(spec, BASE, self.base_z, friction)
        lo, hi = float(self.heights.min()), float(self.heights.max())
        rx, ry = 0.5 * (self.x[-1] - self.x[0]), 0.5 * (self.y[-1] - self.y[0])
        # MuJoCo scales the normalized data by size[2] above the geom's z; size[3] is the depth
        # of the solid below the lowest point. Rows run along +y, columns along +x.
        name = "rough"
        if self.smooth_contact:
            from . import native
            native.install_smooth_heightfield()
            name = native.SMOOTH_HEIGHTFIELD_PREFIX + "_rough"
        spec.add_hfield(name=name, size=[rx, ry, max(hi - lo, 1e-6), 0.05],
                        nrow=self.y.size, ncol=self.x.size,
                        userdata=((self.heights - lo) / max(hi - lo, 1e-6)).ravel().tolist())
        geom = spec.worldbody.add_geom(name="rough", type=mujoco.mjtGeom.mjGEOM_HFIELD,
                                       hfieldname=name,
                                       pos=[self.x[0] + rx, self.y[0] + ry, lo])
        _geom_flags(geom, friction)
        geom.solref = [self.contact_time_constant, 1.0]
        geom.solmix = 1e3  # the pair's solref is the solmix-weighted mean: the heightfield's

    def height(self, x: float, y: float) -> float:
        """Ground height [m] at (x, y): bilinear in the grid (MuJoCo splits each cell into two
        triangles; the two differ by less than the height's curvature over one cell)."""
        u = np.clip((x - self.x[0]) / self.cell, 0.0, self.x.size - 1.000001)
        v = np.clip((y - self.y[0]) / self.cell, 0.0, self.y.size - 1.000001)
        i, j = int(v), int(u)
        a, b = v - i, u - j
        h = self.heights
        return float((1 - a) * ((1 - b) * h[i, j] + b * h[i, j + 1])
                     + a * ((1 - b) * h[i + 1, j] + b * h[i + 1, j + 1]))

    def configure(self, model, robot_geoms) -> None:
        pass


@dataclass(frozen=True)
class Compliant:
    """Flat floor at z = 0 whose normal force on each robot geom resting on it is stiffness x
    sinkage (stiffness [N/m]) plus damping x sinkage rate, damping = 2 damping_ratio
    sqrt(stiffness load_mass) [N s/m] (load_mass [kg]: the mass one foot carries; the scenario
    gives it). A foot sunk deeper than its sphere reaches past the shank also bears on the shank
    (a second contact, in parallel)."""
    stiffness: float = 1e3
    load_mass: float = 1.0
    damping_ratio: float = 1.0
    # Constant impedance d of MuJoCo's soft contact. The contact force is
    # f = -(k r + b v) - (1/R) r'' with R = (1 - d)/d * A (A: the contact's approximate inverse
    # mass): the last term acts like an added mass 1/R on the foot, d/(1 - d) times the foot's
    # own constraint mass; a small d keeps it small (0.05: 1/19 of it).
    impedance: float = 0.05

    def height(self, x: float, y: float) -> float:
        return 0.0

    @property
    def damping(self) -> float:
        return 2.0 * self.damping_ratio * np.sqrt(self.stiffness * self.load_mass)

    def add_to(self, spec, friction: float) -> None:
        _add_plane(spec, BASE, 0.0, friction)

    def configure(self, model, robot_geoms) -> None:
        """Per-geom solref in MuJoCo's direct form (-k', -b') and a constant impedance d.

        MuJoCo scales them to K = k'/d^2, B = b'/d and asks for the reference acceleration
        aref = -B v - K d r (r: penetration, v: its rate); its normal force f solves
        R f = aref - a with R = (1 - d)/d A, so with the contact not accelerating (a = 0)
        f = -(k' r + b' v) / ((1 - d) A). Hence k' = stiffness (1 - d) A and b' = damping (1 - d) A
        give stiffness [N/m] and damping [N s/m] whatever the geom's constraint mass. A: the
        geom's body's translational invweight0, MuJoCo's approximation for a contact normal
        against the static world (a constant of the model). robot_geoms: every robot geom that
        can touch the ground (a shank sunk into soft ground bears on it too)."""
        if model.opt.cone != mujoco.mjtCone.mjCONE_ELLIPTIC:
            # A pyramidal cone has no normal row of its own: the relation above does not hold
            # (measured: a 5 kg ball sank 0.26 mm instead of 49 mm).
            raise InputError("Compliant ground needs the elliptic friction cone")
        d = self.impedance
        solimp = [d, d, 0.001, 0.5, 2.0]
        base = model.geom(BASE).id
        refs = []
        for g in robot_geoms:
            A = float(model.body_invweight0[model.geom_bodyid[g], 0])
            ref = np.array([-self.stiffness * (1 - d) * A, -self.damping * (1 - d) * A])
            model.geom_solref[g], model.geom_solimp[g] = ref, solimp
            model.geom_solmix[g] = 1.0
            refs.append(ref)
        # The floor: its solmix 0 lets the foot's solimp win the weighted mix, and its solref the
        # least negative of the feet's, so that the element-wise minimum MuJoCo takes for direct
        # solrefs is also the foot's.
        model.geom_solref[base] = np.max(refs, axis=0)
        model.geom_solimp[base] = solimp
        model.geom_solmix[base] = 0.0
