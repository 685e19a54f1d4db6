"""Print the inertia numbers and the standing geometry of models/quadruped/quadruped.urdf.

Every link is a uniform primitive about its centre of mass, with its axes along the link frame, so
each tensor is diagonal. The trunk inertia is not derived here: the issue specifies it.
"""
import numpy as np

LEG = 0.25  # [m] thigh and shank length (hip pitch -> knee -> foot centre)


def cylinder(m, r, length, axis):
    """Solid cylinder: m (3 r^2 + l^2) / 12 across, m r^2 / 2 about its axis (0 x, 1 y, 2 z)."""
    diag = np.full(3, m * (3 * r**2 + length**2) / 12)
    diag[axis] = m * r**2 / 2
    return diag


def sphere(m, r):
    return np.full(3, 2 * m * r**2 / 5)


LINKS = {
    # hip: the hip pitch motor housing, a cylinder r 0.04, l 0.06 coaxial with the pitch axis (y)
    "hip": (0.6, cylinder(0.6, 0.04, 0.06, 1)),
    # thigh: r 0.035, l 0.25 along z (r chosen so that Izz = 6e-4 as for a ~7 cm wide thigh)
    "thigh": (1.0, cylinder(1.0, 0.035, LEG, 2)),
    # shank: thin rod r 0.015, l 0.25 along z
    "shank": (0.25, cylinder(0.25, 0.015, LEG, 2)),
    # foot: solid sphere r 0.02 (the contact sphere)
    "foot": (0.05, sphere(0.05, 0.02)),
}

if __name__ == "__main__":
    for name, (m, diag) in LINKS.items():
        ixx, iyy, izz = (f"{v:.6g}" for v in diag)
        print(f'{name:6s} m={m:<5} ixx="{ixx}" iyy="{iyy}" izz="{izz}"')
    total = 10.0 + 4 * sum(m for m, _ in LINKS.values())
    print(f"total mass {total:.6g} kg, weight {total * 9.81:.6g} N")
    # Standing pose: hip pitch a, knee -2a. Thigh direction Ry(a) (0,0,-1) = (-sin a, 0, -cos a),
    # shank direction Ry(-a) (0,0,-1) = (sin a, 0, -cos a): the x offsets cancel and the foot centre
    # lies 2 L cos a straight below the hip pitch axis.
    a = 0.9
    depth = 2 * LEG * np.cos(a)
    print(f"foot centre {depth:.6f} m below the hip pitch axis; trunk height {depth + 0.02:.6f} m "
          f"with a 0.02 m foot sphere on flat ground")
