#include "edsp/actuator_bridge/virtual_rig_backend.h"

#include <algorithm>

#include <cstring>
#include <thread>

#include <fmt/format.h>

namespace edsp {

VirtualRigBackend::VirtualRigBackend(std::string segment_prefix, mode_t permissions, std::int64_t timeout_us)
    : prefix_(std::move(segment_prefix)), permissions_(permissions), timeout_us_(timeout_us) {}

bool VirtualRigBackend::Configure(const PlatformConfig&, std::string* error) {
  if (!lifecycle_.Allows(BackendTransition::kConfigure, error)) return false;
  ShmChannelSpec spec{DriveCommandSegment(prefix_), kDriveImageCommandFingerprint, 16, sizeof(DriveImageCommand),
                      permissions_};
  auto writer = ShmWriter::Open(spec);
  if (!writer.ok()) {
    *error = writer.message;
    return false;
  }
  commands_ = std::move(writer.value);
  return lifecycle_.Take(BackendTransition::kConfigure, error);
}

bool VirtualRigBackend::Activate(std::string* error) {
  if (!lifecycle_.Allows(BackendTransition::kActivate, error)) return false;
  ShmChannelSpec spec{DriveFeedbackSegment(prefix_), kDriveImageFeedbackFingerprint, 16, sizeof(DriveImageFeedback),
                      permissions_};
  for (int attempt = 0; attempt < 500 && feedback_ == nullptr; ++attempt) {
    auto reader = ShmReader::Open(spec);
    if (reader.ok()) {
      feedback_ = std::move(reader.value);
    } else if (reader.error != ShmError::kNotFound && reader.error != ShmError::kNotReady) {
      *error = reader.message;
      return false;
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  if (feedback_ == nullptr) {
    *error = "no drive feedback on " + spec.segment_name + " after 5 s (is edsp-rig running?)";
    return false;
  }
  // Wait for the first feedback so the bridge starts from the real position.
  if (!feedback_->Wait(std::chrono::seconds(5))) {
    *error = "the drives publish no feedback on " + spec.segment_name;
    return false;
  }
  return lifecycle_.Take(BackendTransition::kActivate, error);
}

void VirtualRigBackend::Deactivate() {
  if (!lifecycle_.Take(BackendTransition::kDeactivate)) return;  // not active: nothing to stop
  Publish(0, DriveSetpoint{}, false);
}

void VirtualRigBackend::Cleanup() {
  if (!lifecycle_.Take(BackendTransition::kCleanup)) return;
  feedback_.reset();
  commands_.reset();
}

bool VirtualRigBackend::Publish(std::int64_t now_utime, const DriveSetpoint& s, bool enable) {
  DriveImageCommand c{};
  c.utime = s.utime != 0 ? s.utime : now_utime;  // the instant the target is for
  c.cycle = ++cycle_;
  c.enable = enable ? 1 : 0;
  std::memcpy(c.motor_angle_rad, s.motor_angle_rad.data(), sizeof c.motor_angle_rad);
  std::memcpy(c.motor_velocity_rad_s, s.motor_velocity_rad_s.data(), sizeof c.motor_velocity_rad_s);
  return commands_->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
    std::memcpy(buffer, &c, sizeof c);
    return sizeof c;
  }) != 0;
}

bool VirtualRigBackend::Write(std::int64_t now_utime, const DriveSetpoint& setpoint) {
  if (lifecycle_.state() != BackendState::kActive) return false;  // motion only while active
  return Publish(now_utime, setpoint, true);
}

bool VirtualRigBackend::Read(std::int64_t now_utime, DriveFeedback* feedback) {
  if (feedback_ != nullptr) {
    feedback_->SkipToLatest();
    DriveImageFeedback f{};
    const TakeStatus status = feedback_->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
      if (size != sizeof f) return false;
      std::memcpy(&f, data, sizeof f);
      return true;
    });
    if (status == TakeStatus::kMessage) {
      for (int i = 0; i < 6; ++i) {
        last_.motor_angle_rad[i] = f.motor_angle_rad[i];
        last_.motor_velocity_rad_s[i] = f.motor_velocity_rad_s[i];
        last_.status[i] = static_cast<DriveStatus>(f.status[i]);
      }
      last_.utime = f.utime;
      heard_ = true;
      silence_.Heard(now_utime);
    } else {
      silence_.Missed(now_utime);
    }
  }
  *feedback = last_;
  // A drive in fault (its following error past the window) has braked: the
  // others must stop too, which the bridge does for drives it has lost.
  const bool faulted =
      std::any_of(last_.status.begin(), last_.status.end(), [](DriveStatus s) { return s == DriveStatus::kFault; });
  return !faulted && heard_ && silence_.silent_us() <= timeout_us_;
}

std::string VirtualRigBackend::Detail() const {
  // Worded the same for the whole outage: the bridge reports each new reason once.
  if (!heard_) return DriveFeedbackSegment(prefix_) + ": no feedback from the drives yet";
  for (int i = 0; i < 6; ++i) {
    if (last_.status[i] == DriveStatus::kFault) return fmt::format("drive {} in fault (braked)", i + 1);
  }
  if (silence_.silent_us() > timeout_us_) {
    return fmt::format("{}: no feedback through {:.0f} ms of this bridge's own cycles", DriveFeedbackSegment(prefix_),
                       static_cast<double>(timeout_us_) * 1e-3);
  }
  return "";
}

}  // namespace edsp
