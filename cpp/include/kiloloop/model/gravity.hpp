#pragma once
// Standard gravity, one definition for every source that needs the number (the models' own
// gravity vectors live in their configs).
namespace kiloloop {

inline constexpr double kGravity = 9.81;  // [m/s^2]

}  // namespace kiloloop
