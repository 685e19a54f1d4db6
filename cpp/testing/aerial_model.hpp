#pragma once
// The aerial manipulator of models/aerial_manipulator/, loaded as the arm chain (body -> ee_link)
// the AerialController and FloatingBaseRne expect.
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop::testing {

inline RobotModelPtr load_aerial() {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  const Status s = model_from_urdf_file(
      std::string(KILOLOOP_MODELS_DIR) + "/aerial_manipulator/aerial_manipulator.urdf", "",
      "ee_link", model.get(), &why);
  EXPECT_EQ(s, Status::kOk) << why;
  return model;
}

}  // namespace kiloloop::testing
