"""What an aerial robot file does not say, derived from its URDF and rotors (robot-file issue 11
extends this: hover thrust, gains from the composite inertia and the rotor bandwidth...)."""
from __future__ import annotations


def summary(robot, model) -> list[str]:
    from ..sil.aerial_plant import AerialPlant

    plant = AerialPlant(robot.urdf, robot.sim)
    return [f"  plant: {plant.model.nbody - 1} bodies, {plant.nq} arm joints, "
            f"{plant.n_rotors} rotors"]
