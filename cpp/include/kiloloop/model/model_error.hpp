#pragma once
// The one way model building and loading report a refusal: the reason into *why (when asked
// for), kModelError out.
#include <string>

#include "kiloloop/status.hpp"

namespace kiloloop {

inline Status model_error(std::string* why, const std::string& msg) {
  if (why) *why = msg;
  return Status::kModelError;
}

}  // namespace kiloloop
