"""What a quadruped's robot file does not say, derived from its URDF (robot-file issue 10 extends
this: stand height, gains from masses and inertias, contact thresholds...)."""
from __future__ import annotations


def summary(robot, model) -> list[str]:
    from ..sil.floating_plant import FloatingBasePlant

    plant = FloatingBasePlant(robot.urdf, robot.sim)
    return [f"  plant: {plant.model.nbody - 1} bodies, {plant.nq} actuated joints, "
            f"feet {', '.join(plant.feet)}"]
