#include "sil/smooth_heightfield.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "sil/mujoco_api.hpp"

namespace kiloloop::sil {
namespace {

mjfCollision g_stock = nullptr;  // MuJoCo's heightfield : sphere collider (unmarked heightfields)

bool marked(const mjModel* m, int hfield) {
  const int adr = m->name_hfieldadr[hfield];
  return adr >= 0 && std::strncmp(m->names + adr, kSmoothHeightfieldPrefix,
                                  std::strlen(kSmoothHeightfieldPrefix)) == 0;
}

}  // namespace

bool sphere_on_bilinear(const float* data, int nrow, int ncol, double rx, double ry, double elevation,
                        const double c[3], double r, double margin, double* dist, double pos[3],
                        double normal[3]) noexcept {
  if (nrow < 2 || ncol < 2 || !(rx > 0) || !(ry > 0)) return false;
  const double cell_x = 2.0 * rx / (ncol - 1), cell_y = 2.0 * ry / (nrow - 1);  // [m]
  const double u = (c[0] + rx) / cell_x, v = (c[1] + ry) / cell_y;              // [cells]
  if (!(u >= 0.0 && u <= ncol - 1 && v >= 0.0 && v <= nrow - 1)) return false;  // off the grid (or NaN)
  const int j = std::min(static_cast<int>(u), ncol - 2), i = std::min(static_cast<int>(v), nrow - 2);
  const double b = u - j, a = v - i;  // [0, 1] within the cell
  const double h00 = elevation * data[i * ncol + j], h01 = elevation * data[i * ncol + j + 1];
  const double h10 = elevation * data[(i + 1) * ncol + j], h11 = elevation * data[(i + 1) * ncol + j + 1];
  const double h = (1 - a) * ((1 - b) * h00 + b * h01) + a * ((1 - b) * h10 + b * h11);  // [m]
  // The surface's slopes at (u, v) [m/m]; the normal of its tangent plane there.
  const double sx = ((1 - a) * (h01 - h00) + a * (h11 - h10)) / cell_x;
  const double sy = ((1 - b) * (h10 - h00) + b * (h11 - h01)) / cell_y;
  const double inv = 1.0 / std::sqrt(1.0 + sx * sx + sy * sy);
  normal[0] = -sx * inv;
  normal[1] = -sy * inv;
  normal[2] = inv;
  // Distance of the centre from that plane (through (x, y, h)), then of the sphere's surface.
  const double centre = (c[2] - h) * normal[2];
  *dist = centre - r;
  if (*dist > margin) return false;
  const double mid = r + 0.5 * *dist;  // the midpoint of the sphere's deepest point and the plane
  for (int k = 0; k < 3; ++k) pos[k] = c[k] - mid * normal[k];
  return true;
}

int smooth_heightfield_sphere(const mjModel* m, mjData* d, mjPreContact* con, int g1, int g2,
                              mjtNum margin) {
  const int hf = m->geom_dataid[g1];
  if (!marked(m, hf)) return g_stock ? g_stock(m, d, con, g1, g2, margin) : 0;
  const mjtNum* x1 = d->geom_xpos + 3 * g1;
  const mjtNum* R1 = d->geom_xmat + 9 * g1;  // row-major: world = R1 local
  const mjtNum* x2 = d->geom_xpos + 3 * g2;
  const double w[3] = {x2[0] - x1[0], x2[1] - x1[1], x2[2] - x1[2]};
  double c[3];  // the sphere's centre in the heightfield geom's frame: R1^T (x2 - x1)
  for (int k = 0; k < 3; ++k) c[k] = R1[k] * w[0] + R1[3 + k] * w[1] + R1[6 + k] * w[2];
  const mjtNum* size = m->hfield_size + 4 * hf;  // radius x, radius y, elevation, base
  double dist, pos[3], n[3];
  if (!sphere_on_bilinear(m->hfield_data + m->hfield_adr[hf], m->hfield_nrow[hf], m->hfield_ncol[hf],
                          size[0], size[1], size[2], c, m->geom_size[3 * g2], margin, &dist, pos, n))
    return 0;
  con[0].dist = dist;
  for (int k = 0; k < 3; ++k) {
    con[0].pos[k] = x1[k] + R1[3 * k] * pos[0] + R1[3 * k + 1] * pos[1] + R1[3 * k + 2] * pos[2];
    con[0].normal[k] = R1[3 * k] * n[0] + R1[3 * k + 1] * n[1] + R1[3 * k + 2] * n[2];
    con[0].tangent[k] = 0.0;  // MuJoCo completes the frame from the normal
  }
  return 1;
}

bool install_smooth_heightfield(std::string* why) {
  if (!mujoco_api_loaded()) {
    *why = "libmujoco is not loaded (kiloloop.sil.native loads it)";
    return false;
  }
  mjfCollision& slot = mujoco_api().collision_table[mjGEOM_HFIELD][mjGEOM_SPHERE];
  if (slot != &smooth_heightfield_sphere) {
    g_stock = slot;
    slot = &smooth_heightfield_sphere;
  }
  return true;
}

}  // namespace kiloloop::sil
