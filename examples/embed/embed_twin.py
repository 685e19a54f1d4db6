"""The Python twin of embed_demo (main.cpp, encoder-replay mode) through the `kiloloop` module.

    python examples/embed/embed_twin.py models/ur5/ur5.urdf > twin.txt
    diff <(build/embed/embed_demo models/ur5/ur5.urdf) twin.txt

Same model, same default ComputedTorqueController, same QuinticTrajectory and the same replayed
encoders, so every controller input equals the C++ one bit for bit; the compiled core is the same
code, so the torques must be bit-identical too (tests/test_embed_example.py checks all of them).

Bit identity needs the *inputs* to be identical, which is why the encoders are replayed from a
closed-form expression of the tick rather than integrated from a plant: a plant's state goes
through a linear solve, and numpy's LU and Eigen's LDLT round differently. The replay uses
kl.detmath.sin/cos on Python floats (musl's, which std::sin/std::cos are in a program linked with
kiloloop::core; not math.sin, the system's libm, nor numpy's SIMD versions) and evaluates each
expression in the same order as main.cpp.
"""
import math
import sys

import numpy as np

import kiloloop as kl

TICKS = 1000
DT = 0.001  # [s] the 1 kHz tick

# The task (same literals as kTimes and kWaypoints in main.cpp): one waypoint per row.
TIMES = [0.0, 0.4, 0.9]  # [s]
WAYPOINTS = [  # [rad]
    [0.0, -1.57, 1.57, -1.57, -1.57, 0.0],
    [0.5, -1.2, 1.2, -1.2, -1.3, 0.4],
    [1.0, -1.0, 0.8, -1.4, -1.0, 0.8],
]

# Replayed encoders (kPositionNoise ... kVelocityRate in main.cpp).
POSITION_NOISE = 1e-3  # [rad]
POSITION_RATE = 0.01  # [rad/tick] per joint index
VELOCITY_NOISE = 1e-2  # [rad/s]
VELOCITY_RATE = 0.007  # [rad/tick] per joint index


def replay_encoders(tick, q_ref, qd_ref, q, qd):
    """main.cpp's replay_encoders(): writes q, qd (numpy views into the controller input)."""
    for j in range(len(q)):
        k = float(j + 1)
        # float(...) keeps every operation on Python floats (IEEE doubles), as in C++.
        q[j] = float(q_ref[j]) + POSITION_NOISE * kl.detmath.sin(POSITION_RATE * tick * k)
        qd[j] = float(qd_ref[j]) + VELOCITY_NOISE * kl.detmath.cos(VELOCITY_RATE * tick * k)


def run(urdf_path):
    """The 1000-tick loop; returns a list of (tick, [tau_0 .. tau_{nq-1}], status as int)."""
    model = kl.RobotModel.from_urdf(str(urdf_path))
    if model.nq != len(WAYPOINTS[0]):
        raise ValueError(f"the waypoint table is written for 6 joints, the model has {model.nq}")
    controller = kl.ComputedTorqueController(model)  # the library's defaults
    trajectory = kl.QuinticTrajectory(np.array(WAYPOINTS, dtype=float), np.array(TIMES, dtype=float))
    inp = controller.make_input()
    out = controller.make_output()

    rows = []
    for tick in range(TICKS):
        inp.t = tick * DT
        inp.stamp = inp.t
        # Writes straight into the input's vectors (numpy views), like sample() into Eigen::Ref.
        trajectory.sample_into(inp.t, inp.q_ref, inp.qd_ref, inp.qdd_ref)
        replay_encoders(tick, inp.q_ref, inp.qd_ref, inp.q, inp.qd)
        status = controller.step(inp, out)
        rows.append((tick, [float(x) for x in out.tau], int(status)))
    return rows


def c_hex(x):
    """glibc printf("%a") spelling of a double: float.hex() without the mantissa's trailing zeros."""
    if not math.isfinite(x):
        return repr(x)  # 'nan', 'inf', '-inf' as glibc prints them
    mantissa, exponent = x.hex().split("p")
    if "." in mantissa:
        mantissa = mantissa.rstrip("0").rstrip(".")
    return f"{mantissa}p{exponent}"


def format_row(tick, tau, status):
    return " ".join([str(tick), *(c_hex(t) for t in tau), str(status)])


def main(argv):
    if len(argv) != 2:
        print(f"usage: {argv[0]} <robot.urdf>", file=sys.stderr)
        return 2
    rows = run(argv[1])
    for row in rows:
        print(format_row(*row))
    failed = sum(status < 0 for _, _, status in rows)
    print(f"embed_twin: {len(rows)} ticks (encoder replay), {failed} failed", file=sys.stderr)
    return 0 if failed == 0 else 3


if __name__ == "__main__":
    sys.exit(main(sys.argv))
