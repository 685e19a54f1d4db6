"""Print the <inertial> blocks of models/ur5/ur5.urdf, so a reviewer can reproduce them.

Masses and centres of mass are Universal Robots' published UR5 values (CoM given in DH frame i).
Inertias are solid-cylinder approximations; each tensor is diagonal in the URDF link frame because
every cylinder axis is chosen along a link-frame axis.
"""
import numpy as np

# Standard DH table (a, alpha, d) of the UR5.
DH = [(0.0, np.pi / 2, 0.089159), (-0.425, 0.0, 0.0), (-0.39225, 0.0, 0.0),
      (0.0, np.pi / 2, 0.10915), (0.0, -np.pi / 2, 0.09465), (0.0, 0.0, 0.0823)]
MASS = [3.7, 8.393, 2.275, 1.219, 1.219, 0.1879]
COM_DH = [(0, -0.02561, 0.00193), (0.2125, 0, 0.11336), (0.15, 0, 0.0265),
          (0, -0.0018, 0.01634), (0, 0.0018, 0.01634), (0, 0, -0.001159)]
# (radius, length, axis in the link frame): the shoulder and wrist 1/2 bodies are the motor housings
# of the next joint (coaxial with it, link-frame y); upper arm and forearm are tubes along link x;
# wrist 3 is the flange disc about its own joint axis (z).
CYL = [(0.06, 0.15, 1), (0.06, 0.425, 0), (0.05, 0.39225, 0),
       (0.045, 0.12, 1), (0.045, 0.12, 1), (0.045, 0.025, 2)]
NAMES = ["shoulder_link", "upper_arm_link", "forearm_link",
         "wrist_1_link", "wrist_2_link", "wrist_3_link"]


def com_in_link_frame(c, a, alpha, d):
    # link i frame -> DH frame i is Tz(d) Tx(a) Rx(alpha); map the point c from DH frame i back.
    x, y, z = c
    ca, sa = np.cos(alpha), np.sin(alpha)
    return np.array([a + x, ca * y - sa * z, d + sa * y + ca * z])


def cylinder_inertia(m, r, length, axis):
    transverse = m * (3 * r**2 + length**2) / 12
    diag = np.full(3, transverse)
    diag[axis] = m * r**2 / 2
    return diag


def block(name, m, com, diag):
    com = np.where(np.abs(com) < 1e-15, 0.0, com)  # print 0 rather than -0 or 1e-17
    return (f"<!-- {name} -->\n<inertial>\n"
            f"  <origin xyz=\"{com[0]:.6g} {com[1]:.6g} {com[2]:.6g}\" rpy=\"0 0 0\"/>\n"
            f"  <mass value=\"{m}\"/>\n"
            f"  <inertia ixx=\"{diag[0]:.6g}\" ixy=\"0\" ixz=\"0\" iyy=\"{diag[1]:.6g}\" iyz=\"0\""
            f" izz=\"{diag[2]:.6g}\"/>\n</inertial>")


if __name__ == "__main__":
    # Base: 4.0 kg cylinder r 0.075, h 0.06 standing on the mounting plane (not used by fixed-base
    # dynamics, but MuJoCo and KDL both want a mass on the root link).
    print(block("base_link", 4.0, np.array([0, 0, 0.03]), cylinder_inertia(4.0, 0.075, 0.06, 2)))
    for i in range(6):
        a, alpha, d = DH[i]
        com = com_in_link_frame(COM_DH[i], a, alpha, d)
        print(block(NAMES[i], MASS[i], com, cylinder_inertia(MASS[i], *CYL[i])))
