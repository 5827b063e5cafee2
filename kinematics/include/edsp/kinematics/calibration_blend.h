#pragma once
// The calibration in force, and a switch to another while the platform
// moves: the correction goes from the old calibration's (none: zero) to the
// new one's linearly over a blend of setpoint time, both compensators
// running side by side meanwhile, so no step reaches the drives whatever
// the two models say (docs/calibration.md, "Switching live").
//
// The blend advances by the setpoint time between consecutive setpoints,
// at most kMaxAdvance_us per setpoint and never back: setpoint stamps are
// the sender's word (a replayed log, a late planner, a stream that starts
// again), and a jump in them must not jump the correction.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "edsp/kinematics/calibration.h"

namespace edsp::calibration {

class CalibrationBlend {
 public:
  static constexpr double kMaxAdvance_us = 10000.0;  // 1% of a 1 s blend

  // `in_force` (null: the nominal model alone) applies from the first Step.
  CalibrationBlend(std::unique_ptr<LegCompensator> in_force, std::int64_t blend_us);

  // Blends to `next` (null: the nominal model) from the next Step on, over
  // blend_us of setpoint time. A switch while another is blending is
  // refused (false, *why_not says how much of it is left): the outgoing mix
  // of two models has no third to blend from.
  bool SwitchTo(std::unique_ptr<LegCompensator> next, std::string* why_not);

  // The calibration in force is not in the drives yet (a start where they
  // hold at the nominal model's command, or partway): from the next Step on
  // it blends in from `weight` of it (0: none) to all of it over `blend_us`
  // of setpoint time (this blend's own length; a switch's stays blend_us()).
  // The caller scales the correction it already has for this setpoint.
  void BlendInFrom(double weight, std::int64_t blend_us);

  // The correction for one setpoint (LegCompensator::Step's arguments),
  // blended while a switch is under way.
  LegCompensator::Correction Step(std::int64_t setpoint_utime, const Pose& pose, const Vector6& pose_velocity,
                                  const Vector6& pose_acceleration, const Vector6& command_m);

  // The calibration switched to last (the one in force once no blend
  // runs); null: none.
  const CalibrationModel* target() const { return next_ ? &next_->calibration() : nullptr; }
  // While blending, the one blended from (null: none).
  const CalibrationModel* source() const { return previous_ ? &previous_->calibration() : nullptr; }
  bool blending() const { return blending_; }
  // How far the blend has come, 0..1 (1 when none runs).
  double weight() const { return blending_ ? elapsed_us_ / static_cast<double>(running_us_) : 1.0; }
  std::int64_t blend_us() const { return blend_us_; }
  std::int64_t running_blend_us() const { return running_us_; }  // the blend under way's length

 private:
  // Moves the blend on to `setpoint_utime` and returns the new
  // calibration's weight there; ends the blend (dropping the old
  // compensator) when it reaches 1.
  double AdvanceBlend(std::int64_t setpoint_utime);

  std::unique_ptr<LegCompensator> previous_;  // blended from; null: nominal
  std::unique_ptr<LegCompensator> next_;      // in force (or blended to); null: nominal
  std::int64_t blend_us_;
  std::int64_t running_us_;  // the blend under way's: blend_us_ for a switch
  bool blending_ = false;
  double elapsed_us_ = 0.0;  // of the blend, in setpoint time
  std::optional<std::int64_t> last_setpoint_utime_;
};

}  // namespace edsp::calibration
