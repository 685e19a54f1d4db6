#pragma once
// One contact per sphere on a heightfield, from the smooth (bilinear) surface through its grid
// points, in place of MuJoCo's sphere : heightfield collider for the heightfields a terrain marks
// (name prefix kSmoothHeightfieldPrefix; every other heightfield keeps MuJoCo's collider).
//
// Why: MuJoCo collides a convex geom with a heightfield prism by prism (two triangular prisms
// per cell), one contact per prism touched. A 20 mm foot sphere on the 2 cm grid of
// quadruped-rough made 1 to 7 contacts at once (measured standing on a flat heightfield: 7 on one
// foot), each a constraint of its own, so the ground's stiffness and friction changed from one
// landing to the next; and a foot sunk below a cell's surface by more than its distance to the
// cell's edges met the prisms' vertical side faces, whose normals pushed it sideways from both
// sides and whose friction held it down (up to 900 N of downward force on a 12 kg robot). Go1 at
// 35 ms of actuation delay fell on seeds 0-4 on a FLAT heightfield while it trots on MuJoCo's
// plane. Here the ground under a sphere is the plane tangent to the bilinear surface below its
// centre: on a flat heightfield exactly the plane's single contact, and on bumps long against
// the foot (quadruped-rough's are a body height long) the surface a sphere rolls on.
//
// The surface is the one `Rough.height` in python/kiloloop/sil/terrain.py describes (bilinear in
// each cell), so the scenario's metrics and the plant's contacts read the same ground.
#include <string>

#include <mujoco/mujoco.h>

namespace kiloloop::sil {

inline constexpr const char* kSmoothHeightfieldPrefix = "kiloloop_smooth";

// MuJoCo's collision-function signature (mjfCollision): g1 the heightfield geom, g2 the sphere;
// writes at most one contact (normal from the heightfield to the sphere) and returns the count.
// Heightfields without the prefix go to MuJoCo's own function for the pair (the one
// install_smooth_heightfield found in the table).
int smooth_heightfield_sphere(const mjModel* m, mjData* d, mjPreContact* con, int g1, int g2,
                              mjtNum margin);

// The contact of a sphere (centre c [m] in the heightfield geom's frame, radius r) with the
// bilinear surface of heights z(row, col) = elevation * data[row * ncol + col] over
// [-rx, rx] x [-ry, ry] (rows along y, columns along x). False when c is off the grid or farther
// than margin from the surface; else dist (signed, negative in penetration), the midpoint
// between the two surfaces and the unit normal, in that frame.
bool sphere_on_bilinear(const float* data, int nrow, int ncol, double rx, double ry, double elevation,
                        const double c[3], double r, double margin, double* dist, double pos[3],
                        double normal[3]) noexcept;

// Puts smooth_heightfield_sphere into the loaded libmujoco's collision table (mjCOLLISIONFUNC,
// process-wide: MuJoCo's Python bindings and the native loop step with the same library), once;
// the stock function is kept for unmarked heightfields. False with why before load_mujoco_api.
// Call under the GIL, before stepping.
bool install_smooth_heightfield(std::string* why);

}  // namespace kiloloop::sil
