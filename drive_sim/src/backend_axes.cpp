#include "edsp/drive_sim/backend_axes.h"

#include <stdexcept>

#include "edsp/actuator_bridge/drives_config.h"
#include "edsp/node/runtime.h"

namespace edsp::cia402 {

BackendAxes::BackendAxes(std::unique_ptr<DriveBackend> backend, const PlatformConfig& config,
                         const std::array<DriveScaling, kCabinetDrives>& scaling, std::int64_t fieldbus_timeout_us)
    : backend_(std::move(backend)), scaling_(scaling), fieldbus_timeout_us_(fieldbus_timeout_us) {
  if (const std::optional<std::string> problem = ScalingProblem(scaling_)) {
    throw std::runtime_error("the drives' axes: " + *problem);
  }
  std::string error;
  if (!backend_->Configure(config, &error) || !backend_->Activate(&error)) {
    throw std::runtime_error("the drives' axes: " + error);
  }
  Sense(UtimeNow());
  if (!feedback_ok_) throw std::runtime_error("the drives' axes report no position");
  for (std::size_t d = 0; d < held_rad_.size(); ++d) held_rad_[d] = feedback_.motor_angle_rad[d];
}

BackendAxes::~BackendAxes() {
  backend_->Deactivate();
  backend_->Cleanup();
}

void BackendAxes::Sense(std::int64_t now_utime) {
  feedback_ok_ = backend_->Read(now_utime, &feedback_);
  for (std::size_t d = 0; d < readings_.size(); ++d) {
    AxisReading& r = readings_[d];
    r.position = scaling_[d].Counts(feedback_.motor_angle_rad[d]);
    r.velocity = scaling_[d].CountRate(feedback_.motor_velocity_rad_s[d]);
    r.error_code = !feedback_ok_                                ? kErrorPositionSensor
                   : feedback_.status[d] == DriveStatus::kFault ? kErrorDeviceHardware
                                                                : 0;
  }
}

DriveSetpoint BackendAxes::Actuate(std::int64_t now_utime, std::int64_t command_utime,
                                   const std::array<AxisDemand, kCabinetDrives>& demands) {
  DriveSetpoint setpoint;
  setpoint.utime = command_utime;
  const bool command_expired = now_utime - command_utime > fieldbus_timeout_us_;
  for (std::size_t d = 0; d < demands.size(); ++d) {
    const bool follow = demands[d].follow && !command_expired;
    if (follow) {
      setpoint.motor_angle_rad[d] = scaling_[d].ToAngle(demands[d].target);
      setpoint.motor_velocity_rad_s[d] = scaling_[d].ToRate(demands[d].velocity_offset);
    } else {
      // Stopped following this cycle: the brake holds the leg where it is.
      if (followed_[d]) held_rad_[d] = feedback_.motor_angle_rad[d];
      setpoint.motor_angle_rad[d] = held_rad_[d];
      setpoint.motor_velocity_rad_s[d] = 0.0;
    }
    followed_[d] = follow;
  }
  return setpoint;
}

void BackendAxes::Step(double /*dt_s*/, std::int64_t command_utime,
                       const std::array<AxisDemand, kCabinetDrives>& demands) {
  // Sense before acting, as a drive samples its position at the cycle's
  // start: a drive that stops following this cycle holds where its leg
  // stands now, not where it stood a cycle (or a stall) ago.
  const std::int64_t now = UtimeNow();
  Sense(now);
  backend_->Write(now, Actuate(now, command_utime != 0 ? command_utime : now, demands));
}

}  // namespace edsp::cia402
