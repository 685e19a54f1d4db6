#pragma once
// What differs between the three families at init: how a configured controller gives its
// (sized) input and output. One overload per controller; the loop itself is family-blind.
#include <memory>

#include "kiloloop/aerial/aerial_controller.hpp"
#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/quadruped/quadruped_controller.hpp"

namespace firmware {

inline void make_io(const kiloloop::ComputedTorqueController& c, kiloloop::JointControlInput* in,
                    kiloloop::JointControlOutput* out) {
  *in = c.make_input();
  *out = c.make_output();
}

inline void make_io(const kiloloop::QuadrupedController&, kiloloop::QuadrupedInput* in,
                    kiloloop::QuadrupedOutput* out) {
  *in = kiloloop::QuadrupedInput{};  // fixed size: 12 joints
  *out = kiloloop::QuadrupedOutput{};
}

inline void make_io(const kiloloop::AerialController& c, kiloloop::AerialInput* in,
                    kiloloop::AerialOutput* out) {
  *in = c.make_input();
  *out = c.make_output();
}

}  // namespace firmware
