#include "edsp/rig/drive_image_server.h"

#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace edsp {

namespace {
constexpr std::uint32_t kImageSlots = 16;

ShmChannelSpec FeedbackSpec(const std::string& prefix, mode_t permissions) {
  return ShmChannelSpec{DriveFeedbackSegment(prefix), kDriveImageFeedbackFingerprint, kImageSlots,
                        sizeof(DriveImageFeedback), permissions};
}
}  // namespace

DriveImageServer::DriveImageServer(const std::string& prefix, mode_t permissions)
    : prefix_(prefix), mode_(permissions) {
  auto writer = ShmWriter::Open(FeedbackSpec(prefix, permissions));
  if (!writer.ok()) throw std::runtime_error("drive feedback image: " + writer.message);
  feedback_ = std::move(writer.value);
}

void DriveImageServer::NewCommands(std::vector<DriveImageCommand>* commands) {
  if (commands_ == nullptr) {
    ShmChannelSpec spec{DriveCommandSegment(prefix_), kDriveImageCommandFingerprint, kImageSlots,
                        sizeof(DriveImageCommand), mode_};
    auto reader = ShmReader::Open(spec);
    if (!reader.ok()) return;  // no bridge yet
    commands_ = std::move(reader.value);
  }
  // A slot of another size is no command; the ones after it still are.
  for (int taken = 0; taken < static_cast<int>(kImageSlots); ++taken) {
    DriveImageCommand command{};
    const TakeStatus status = commands_->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
      if (size != sizeof command) return false;
      std::memcpy(&command, data, sizeof command);
      return true;
    });
    if (status == TakeStatus::kEmpty) return;
    if (status == TakeStatus::kMessage) commands->push_back(command);
  }
}

void DriveImageServer::PublishFeedback(const DriveFeedback& f, std::int64_t utime, std::int64_t cycle) {
  DriveImageFeedback image{};
  image.utime = utime;
  image.cycle = cycle;
  for (int i = 0; i < 6; ++i) {
    image.motor_angle_rad[i] = f.motor_angle_rad[i];
    image.motor_velocity_rad_s[i] = f.motor_velocity_rad_s[i];
    image.status[i] = static_cast<std::int8_t>(f.status[i]);
  }
  feedback_->Publish([&](std::uint8_t* buffer, std::uint32_t) -> std::int64_t {
    std::memcpy(buffer, &image, sizeof image);
    return sizeof image;
  });
}

ImageRestore RestoreFromImage(const std::string& prefix, mode_t permissions, VirtualRig* rig) {
  ImageRestore result;
  const std::string segment = DriveFeedbackSegment(prefix);
  auto reader = ShmReader::Open(FeedbackSpec(prefix, permissions));
  if (!reader.ok()) {
    if (reader.error != ShmError::kNotFound) result.note = segment + ": " + reader.message;
    return result;
  }
  if (reader.value->WriterAlive()) return result;  // another rig: claiming the ring will say so
  reader.value->RewindToLatest();
  DriveImageFeedback last{};
  const TakeStatus status = reader.value->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
    if (size != sizeof last) return false;
    std::memcpy(&last, data, sizeof last);
    return true;
  });
  if (status != TakeStatus::kMessage) {
    result.note = segment + ": no feedback left to continue from; starting at home";
    return result;
  }
  std::array<double, 6> angles{};
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(last.motor_angle_rad[i])) {
      result.note = segment + ": non-finite motor angle left; starting at home";
      return result;
    }
    angles[static_cast<std::size_t>(i)] = last.motor_angle_rad[i];
  }
  if (!rig->RestoreDrives(angles)) {
    result.note = segment + ": no platform pose fits the motor angles left; starting at home";
    return result;
  }
  result.restored = true;
  result.note =
      "continuing from the drives' last feedback in " + segment + " (absolute encoders); drives off until commanded";
  return result;
}

}  // namespace edsp
