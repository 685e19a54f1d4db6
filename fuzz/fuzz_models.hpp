#pragma once
// Models of the fuzz targets, from models/ (KILOLOOP_MODELS_DIR, overridable by the environment).
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "fuzz_common.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop::fuzz {

// The whole tree, or the chain from the root to `tip` when one is given.
inline RobotModelPtr load_model(const char* relative, const char* tip = "") {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  const std::string path = models_dir() + "/" + relative;
  if (failed(model_from_urdf_file(path, "", tip, model.get(), &why))) {
    std::fprintf(stderr, "kiloloop_fuzz: cannot load %s: %s\n", path.c_str(), why.c_str());
    std::exit(4);
  }
  return model;
}

// Output within +-effort (exactly: clipping is a clamp) and finite.
inline bool within_effort(const Eigen::Ref<const Eigen::VectorXd>& tau,
                          const Eigen::Ref<const Eigen::VectorXd>& effort) {
  if (tau.size() != effort.size()) return false;
  for (Eigen::Index i = 0; i < tau.size(); ++i)
    if (!std::isfinite(tau[i]) || std::abs(tau[i]) > effort[i]) return false;
  return true;
}

// Size mutations: swaps a field with a vector of a wrong size (no allocation while stepping)
// and back afterwards.
struct WrongSize {
  Eigen::VectorXd pool[4];
  Eigen::VectorXd* swapped[4] = {nullptr, nullptr, nullptr, nullptr};
  int used = 0;
  explicit WrongSize(int n) {
    pool[0].setZero(0);
    pool[1].setZero(n > 1 ? n - 1 : 2);
    pool[2].setZero(n + 1);
    pool[3].setZero(1 == n ? 3 : 1);
  }
  void apply(Rng& r, Eigen::VectorXd& field, Desc& d, const char* name) {
    if (used == 4) return;
    Eigen::VectorXd& p = pool[used];
    p.setConstant(r.uniform(-1.0, 1.0));
    field.swap(p);
    swapped[used++] = &field;
    d.add("%s of size %d", name, static_cast<int>(field.size()));
  }
  void undo() {
    while (used > 0) {
      --used;
      swapped[used]->swap(pool[used]);
    }
  }
};

}  // namespace kiloloop::fuzz
