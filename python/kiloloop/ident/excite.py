"""`kiloloop excite`: an excitation run of a robot in the SIL, logged as a real robot's logger
would log it (commanded torques or thrusts, measured joint positions and velocities, IMU).

The plant is the robot file's own ([sim.*] tables, URDF, declared delay): a file with hidden
"true" parameters makes the logs that `kiloloop identify` then reads against the nominal file.
"""
from __future__ import annotations

from ..sil.log import SignalLog

DEFAULT_DURATION = 30.0  # [s] the budget of excitation


def excite(robot, duration: float = DEFAULT_DURATION, seed: int = 0,
           delay: float | None = None, motor_lag: float = 0.0, noise: dict | None = None
           ) -> SignalLog:
    """The excitation log of `robot` (a kl.Robot). delay [s]: the plant's actuation delay (None:
    what the file declares, declared.py); motor_lag [s]: a first-order lag of the produced
    torque or thrust (0: none; a multirotor's rotors have their own time constants); noise: an
    arm's encoder noise, sil/signals.py fields (q_sigma [rad], qd_sigma [rad/s],
    encoder_resolution [rad]; seeded by `seed`)."""
    from ..errors import InputError
    from .declared import declared_delay

    delay = declared_delay(robot) if delay is None else float(delay)
    if robot.kind == "arm":
        from .excite_arm import run

        log = run(robot, duration, seed, delay, motor_lag, noise or {})
    elif robot.kind == "aerial":
        from .excite_aerial import run

        if noise:
            raise InputError("excite: sensor noise is an arm's option here")
        log = run(robot, duration, seed, delay, motor_lag)
    else:
        raise InputError(f"excite: no excitation for a {robot.kind} yet (arms, multirotors)")
    log.info = {"excitation": {"robot": robot.name, "kind": robot.kind, "duration": duration,
                               "seed": int(seed)}}
    return log

