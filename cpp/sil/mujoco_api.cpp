#include "sil/mujoco_api.hpp"

#include <dlfcn.h>

namespace kiloloop::sil {

namespace {
MujocoApi g_api;  // written once by load_mujoco_api (under the GIL), read-only afterwards
bool g_loaded = false;

template <class F>
bool resolve(void* handle, const char* name, F* out, std::string* why) {
  *out = reinterpret_cast<F>(dlsym(handle, name));
  if (!*out) *why = std::string("libmujoco: no symbol ") + name;
  return *out != nullptr;
}
}  // namespace

bool load_mujoco_api(const std::string& path, std::string* why) {
  // RTLD_NOLOAD: only a library this process already loaded (by `import mujoco`); never a copy.
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_NOLOAD);
  if (!handle) {
    *why = "libmujoco at " + path + " is not loaded in this process (import mujoco first)";
    return false;
  }
  MujocoApi api;
  if (!resolve(handle, "mj_step", &api.step, why) || !resolve(handle, "mj_step1", &api.step1, why) ||
      !resolve(handle, "mj_step2", &api.step2, why) ||
      !resolve(handle, "mj_contactForce", &api.contact_force, why) ||
      !resolve(handle, "mj_geomDistance", &api.geom_distance, why) ||
      !resolve(handle, "mj_version", &api.version, why) ||
      !resolve(handle, "mj_versionString", &api.version_string, why) ||
      !resolve(handle, "mjCOLLISIONFUNC", &api.collision_table, why))
    return false;
  if (api.version() != mjVERSION_HEADER) {
    *why = std::string("libmujoco ") + api.version_string() + " differs from the headers kiloloop was built with (" +
           std::to_string(mjVERSION_HEADER) + "): rebuild kiloloop";
    return false;
  }
  g_api = api;
  g_loaded = true;
  return true;  // the handle stays open: the functions must outlive this call
}

const MujocoApi& mujoco_api() noexcept { return g_api; }
bool mujoco_api_loaded() noexcept { return g_loaded; }

}  // namespace kiloloop::sil
