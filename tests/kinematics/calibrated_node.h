#pragma once
// A kinematics node of the paper's platform (session 9) with a calibration,
// as the calibration tests build it.
#include <cstdint>
#include <optional>
#include <utility>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/kinematics_node.h"

namespace edsp::test_support {

enum class CalibrationStart { kFromTheDrives, kInForceAtOnce };

inline KinematicsNode CalibratedNode(std::optional<calibration::CalibrationModel> calibration,
                                     std::int64_t switch_blend_us, CalibrationStart start) {
  KinematicsNodeOptions options;
  options.session_id = 9;
  options.calibration = std::move(calibration);
  options.calibration_blend_us = switch_blend_us;
  options.calibration_starts_from_drives = start == CalibrationStart::kFromTheDrives;
  return KinematicsNode(PlatformModel(Huang2021Config()), options);
}

// The node's command for `sp`, taken at its own stamp; a refusal fails the test.
inline leg_command_t CommandFor(KinematicsNode& node, const pose_setpoint_t& sp) {
  leg_command_t c;
  fault_t fault;
  EXPECT_TRUE(node.HandleSetpoint(sp, sp.utime, &c, &fault)) << fault.reason;
  return c;
}

}  // namespace edsp::test_support
