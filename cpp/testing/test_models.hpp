#pragma once
// Models shared by the C++ tests: the UR5 and the quadruped from models/ and a small planar arm
// from DH.
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "kiloloop/model/dh.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop::testing {

inline std::string ur5_urdf_path() { return std::string(KILOLOOP_MODELS_DIR) + "/ur5/ur5.urdf"; }

inline RobotModelPtr load_ur5() {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  const Status s = model_from_urdf_file(ur5_urdf_path(), "", "", model.get(), &why);
  EXPECT_EQ(s, Status::kOk) << why;
  return model;
}

inline RobotModelPtr load_quadruped() {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  const Status s = model_from_urdf_file(std::string(KILOLOOP_MODELS_DIR) + "/quadruped/quadruped.urdf",
                                        "", "", model.get(), &why);
  EXPECT_EQ(s, Status::kOk) << why;
  return model;
}

// Two-link planar arm in the x-y plane (gravity along -y), point masses at the link tips:
// the textbook system with closed-form M, C and g.
struct PlanarArm {
  double l1 = 0.7, l2 = 0.5, m1 = 2.0, m2 = 1.5;
  std::vector<DhLink> table() const {
    std::vector<DhLink> links(2);
    links[0].a = l1;
    links[0].mass = m1;
    links[1].a = l2;
    links[1].mass = m2;
    // Standard DH frame i sits at the tip of link i: the point mass is at its origin.
    for (auto& l : links) l.limit.effort = 1e6;
    return links;
  }
};

}  // namespace kiloloop::testing
