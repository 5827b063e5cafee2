#pragma once
// The calibration in force, and a switch to another while the platform
// moves: the correction goes from the old calibration's (none: zero) to the
// new one's linearly over a blend of setpoint time, both compensators
// running side by side meanwhile, so no step reaches the drives whatever
// the two models say (docs/calibration.md, "Switching live").

#include <cstdint>
#include <memory>
#include <string>

#include "edsp/kinematics/calibration.h"

namespace edsp::calibration {

class CalibrationBlend {
 public:
  // `in_force` (null: the nominal model alone) applies from the first Step.
  CalibrationBlend(std::unique_ptr<LegCompensator> in_force, std::int64_t blend_us);

  // Blends to `next` (null: the nominal model) from the next Step on, over
  // blend_us of setpoint time. A switch while another is blending is
  // refused (false, *why_not says for how long): the outgoing mix of two
  // models has no third to blend from.
  bool SwitchTo(std::unique_ptr<LegCompensator> next, std::string* why_not);

  // The correction for one setpoint (LegCompensator::Step's arguments),
  // blended while a switch is under way.
  LegCompensator::Correction Step(std::int64_t setpoint_utime, const Pose& pose, const Vector6& pose_velocity,
                                  const Vector6& pose_acceleration, const Vector6& command_m);

  // The calibration in force, or the one being blended to; null: none.
  const CalibrationModel* in_force() const { return next_ ? &next_->calibration() : nullptr; }
  bool blending() const { return blending_; }
  std::int64_t blend_us() const { return blend_us_; }

 private:
  // The weight of the new calibration at `setpoint_utime` (1: blend over).
  double Weight(std::int64_t setpoint_utime);

  std::unique_ptr<LegCompensator> previous_;  // blended from; null: nominal
  std::unique_ptr<LegCompensator> next_;      // in force (or blended to); null: nominal
  std::int64_t blend_us_;
  bool blending_ = false;
  std::int64_t blend_start_utime_ = -1;  // -1: the next setpoint starts it
  std::int64_t last_setpoint_utime_ = -1;
};

}  // namespace edsp::calibration
