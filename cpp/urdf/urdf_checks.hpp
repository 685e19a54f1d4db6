#pragma once
// What urdfdom parses but does not check, checked before kdl_parser and the model see it: the
// link/joint graph is a tree (kdl_parser recurses along it: a loop overflowed the stack), every
// number is finite, masses and inertias are physical, limits are ordered, and something has mass.
// Init time only (allocates, builds messages). Private to the URDF loader.
#include <string>

#include <urdf_model/model.h>

namespace kiloloop::urdf_checks {

// "" when the model is usable, else the first problem, naming the link or joint.
std::string first_problem(const urdf::ModelInterface& model);

}  // namespace kiloloop::urdf_checks
