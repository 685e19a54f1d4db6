#pragma once
// The MuJoCo functions the native loop calls, resolved at run time from the libmujoco that the
// Python `mujoco` module already loaded (dlopen with RTLD_NOLOAD on its path, then dlsym). So the
// loop steps models with the very library that built them, and `import kiloloop` never depends on
// libmujoco being present (a mujoco upgrade only makes the native loop unavailable). The structs
// (mjModel, mjData) come from the headers of the same wheel at build time; load() checks that the
// library's version equals the headers' (mjVERSION_HEADER).
#include <string>

#include <mujoco/mujoco.h>

namespace kiloloop::sil {

struct MujocoApi {
  void (*step)(const mjModel*, mjData*) = nullptr;
  void (*step1)(const mjModel*, mjData*) = nullptr;
  void (*step2)(const mjModel*, mjData*) = nullptr;
  void (*contact_force)(const mjModel*, const mjData*, int, mjtNum*) = nullptr;
  // mj_geomDistance: smallest signed distance between two geoms [m], capped at distmax (uses
  // the data's stack, no heap allocation).
  mjtNum (*geom_distance)(const mjModel*, mjData*, int, int, mjtNum, mjtNum*) = nullptr;
  int (*version)() = nullptr;
  const char* (*version_string)() = nullptr;
  // MuJoCo's table of narrow-phase collision functions by geom type pair (a data symbol, exported
  // so that applications may replace entries: sil/smooth_heightfield.hpp does).
  mjfCollision (*collision_table)[mjNGEOMTYPES] = nullptr;
};

// Resolves the functions from an already-loaded library at `path`. False with why when it is not
// loaded, lacks a symbol or has another version than the headers. Call once, before any run
// (under the GIL: not thread-safe), again only with the same library.
bool load_mujoco_api(const std::string& path, std::string* why);
// The resolved functions; null members until load_mujoco_api succeeded.
const MujocoApi& mujoco_api() noexcept;
bool mujoco_api_loaded() noexcept;

}  // namespace kiloloop::sil
