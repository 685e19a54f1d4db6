"""Per robot family: the compiled controller its firmware runs, the SIL scenario that exercises it
for a back-to-back check, and settings that scenario needs for it (none: the native loop records
the controller's inputs and outputs itself, firmware/recording.py)."""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import InputError


@dataclass(frozen=True)
class Family:
    name: str              # robot file kind
    controller: str        # class in kiloloop (and C++ kiloloop::)
    input: str             # C++ input and output types
    output: str
    header: str            # the controller's C++ header
    scenario: str          # SIL scenario of the b2b run
    settings: dict = field(default_factory=dict)


FAMILIES = {
    "arm": Family("arm", "ComputedTorqueController", "JointControlInput", "JointControlOutput",
                  "kiloloop/control/computed_torque.hpp", "arm-track"),
    "quadruped": Family("quadruped", "QuadrupedController", "QuadrupedInput", "QuadrupedOutput",
                        "kiloloop/quadruped/quadruped_controller.hpp", "quadruped-stand"),
    "aerial": Family("aerial", "AerialController", "AerialInput", "AerialOutput",
                     "kiloloop/aerial/aerial_controller.hpp", "aerial-hover"),
}


def family_of(robot) -> Family:
    if robot.kind not in FAMILIES:
        raise InputError(f"{robot.path}: kind {robot.kind!r} has no firmware family")
    return FAMILIES[robot.kind]
