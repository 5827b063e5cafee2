// edsp-rig: the virtual EDSP standing in for hardware. Serves the drives'
// shared-memory process image to the actuator bridge, steps servo loops,
// screws with true signed PR and the platform at 1 kHz, and publishes the
// laser tracker (EDSP_TRACKER) and ground truth (EDSP_RIG_TRUTH).
//   edsp-rig [--tracker-noise-m 0] [--tracker-rate-hz 1000] [--seed 1]
//            [--tracker-frame x,y,z,roll,pitch,yaw] [--image-prefix edsp]
//            [--drive-watchdog-ms 20] [--config FILE] [--group FILE]
// Drives whose process image stops updating (a frozen or dead bridge) stop
// interpolating after 4 ms and hold; past --drive-watchdog-ms they report
// holding, and EDSP_FAULT says so (and again, as info, when commands return).
#include <cmath>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>

#include "edsp/drive_io/drive_process_image.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/pose_text.h"
#include "edsp/node/fault.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/rig/rig_cycle.h"
#include "edsp/rig/virtual_rig.h"
#include "edsp/transport/bus.h"

namespace edsp {
namespace {

// The drives' side of the process image.
class DriveImage {
 public:
  DriveImage(const std::string& prefix, mode_t permissions) : prefix_(prefix), mode_(permissions) {
    ShmChannelSpec spec{DriveFeedbackSegment(prefix), kDriveImageFeedbackFingerprint, 16,
                        sizeof(DriveImageFeedback), permissions};
    auto writer = ShmWriter::Open(spec);
    if (!writer.ok()) throw std::runtime_error("drive feedback image: " + writer.message);
    feedback_ = std::move(writer.value);
  }

  // The newest command, if any arrived since the last call.
  bool LatestCommand(DriveImageCommand* command) {
    if (commands_ == nullptr) {
      ShmChannelSpec spec{DriveCommandSegment(prefix_), kDriveImageCommandFingerprint, 16,
                          sizeof(DriveImageCommand), mode_};
      auto reader = ShmReader::Open(spec);
      if (!reader.ok()) return false;  // no bridge yet
      commands_ = std::move(reader.value);
    }
    commands_->SkipToLatest();
    return commands_->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
             if (size != sizeof *command) return false;
             std::memcpy(command, data, sizeof *command);
             return true;
           }) == TakeStatus::kMessage;
  }

  void PublishFeedback(const DriveFeedback& f, std::int64_t utime, std::int64_t cycle) {
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

 private:
  std::string prefix_;
  mode_t mode_;
  std::unique_ptr<ShmWriter> feedback_;
  std::unique_ptr<ShmReader> commands_;
};

fault_t WatchdogFault(const std::string& segment, bool tripped, double since_command_s, std::int64_t now) {
  if (tripped) {
    return MakeFault("rig", segment, FaultCode::kStale, fault_t::SEVERITY_ERROR,
                     fmt::format("drive watchdog: no drive command for {:.1f} ms; the drives hold "
                                 "their position", since_command_s * 1e3),
                     now);
  }
  return MakeFault("rig", segment, FaultCode::kStale, fault_t::SEVERITY_INFO,
                   "drive watchdog: drive commands again; the drives follow them", now);
}

// A predecessor killed mid-run left its last drive feedback in the image:
// the motors are still there (absolute encoders), so continue from them.
// Returns what happened, for the log ("" when there was nothing to restore).
std::string RestoreFromImage(const std::string& prefix, mode_t permissions, VirtualRig* rig,
                             bool* restored) {
  *restored = false;
  const std::string segment = DriveFeedbackSegment(prefix);
  ShmChannelSpec spec{segment, kDriveImageFeedbackFingerprint, 16, sizeof(DriveImageFeedback), permissions};
  auto reader = ShmReader::Open(spec);
  if (!reader.ok()) return reader.error == ShmError::kNotFound ? "" : segment + ": " + reader.message;
  if (reader.value->WriterAlive()) return "";  // another rig: opening the writer will say so
  reader.value->RewindToLatest();
  DriveImageFeedback last{};
  const TakeStatus status = reader.value->TryTake([&](const std::uint8_t* data, std::uint32_t size) {
    if (size != sizeof last) return false;
    std::memcpy(&last, data, sizeof last);
    return true;
  });
  if (status != TakeStatus::kMessage) return segment + ": no feedback left to continue from; starting at home";
  std::array<double, 6> angles{};
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(last.motor_angle_rad[i])) return segment + ": non-finite motor angle left; starting at home";
    angles[static_cast<std::size_t>(i)] = last.motor_angle_rad[i];
  }
  if (!rig->RestoreDrives(angles)) return segment + ": no platform pose fits the motor angles left; starting at home";
  *restored = true;
  return "continuing from the drives' last feedback in " + segment + " (absolute encoders); drives off until commanded";
}

int Run(int argc, char** argv) {
  CLI::App app{"edsp-rig: the virtual EDSP with a laser-tracker emulator"};
  NodeOptions node;
  AddNodeOptions(&app, &node);
  RigParameters rig_parameters;
  std::string frame_text, image_prefix;
  app.add_option("--tracker-noise-m", rig_parameters.tracker.noise_sigma_m, "1-sigma per axis")
      ->check(CLI::Range(0.0, 0.01));
  app.add_option("--tracker-rate-hz", rig_parameters.tracker.rate_hz)->check(CLI::Range(1.0, 1000.0));
  app.add_option("--seed", rig_parameters.tracker.seed, "noise seed");
  app.add_option("--tracker-frame", frame_text, "pose of {B} in the tracker frame, x,y,z,roll,pitch,yaw");
  app.add_option("--image-prefix", image_prefix, "process image segment prefix (default: shm_prefix)");
  double watchdog_ms = rig_parameters.watchdog.timeout_s * 1e3;
  app.add_option("--drive-watchdog-ms", watchdog_ms, "no command for this long: the drives report holding")
      ->check(CLI::Range(5.0, 10000.0));
  CLI11_PARSE(app, argc, argv);
  rig_parameters.watchdog.timeout_s = watchdog_ms * 1e-3;

  const PlatformConfig config = LoadConfigFile(node.config_path);
  rig_parameters.nominal = config;
  rig_parameters.effects = LoadRigEffects(node.config_path);  // [rig.effects]: how this rig differs
  if (!frame_text.empty()) rig_parameters.tracker.X_TB = ParsePoseText(frame_text);
  const TransportConfig transport = TransportFor(node);
  InstallStopSignals();
  VirtualRig rig(rig_parameters);
  const std::string prefix = image_prefix.empty() ? transport.shm_prefix : image_prefix;
  bool restored = false;
  const std::string restore_note = RestoreFromImage(prefix, transport.shm_permissions, &rig, &restored);
  DriveImage image(prefix, transport.shm_permissions);
  const std::string command_segment = DriveCommandSegment(prefix);
  Bus bus(transport);
  auto tracker_out = bus.Advertise<tracker_point_t>("EDSP_TRACKER");
  auto truth_out = bus.Advertise<rig_truth_t>("EDSP_RIG_TRUTH");
  auto faults = bus.Advertise<fault_t>("EDSP_FAULT");
  auto status_out = bus.Advertise<node_status_t>("EDSP_STATUS");
  NodeStatus status("rig");
  if (!restore_note.empty()) {
    std::fprintf(stderr, "edsp-rig: %s\n", restore_note.c_str());
    faults.Publish(MakeFault("rig", DriveFeedbackSegment(prefix), FaultCode::kProcess,
                             restored ? fault_t::SEVERITY_INFO : fault_t::SEVERITY_WARNING, restore_note,
                             UtimeNow()));
  }
  status.SetState(node_status_t::STATE_RUNNING);
  // The drives' cycle on the host's grid, 100 µs after the bridge's write
  // (drives on their master's distributed clock): a setpoint reaches them
  // 0.5 ms after the planner's tick, or a cycle later when the bridge wrote
  // it late. A command is continued by at most 2.5 ms, where the bridge stops
  // the feed-forward of a command it has not renewed (kFeedForwardLapseUs);
  // the drives' watchdog holds them after 20 ms.
  RateClock clock(std::chrono::milliseconds(1), std::chrono::microseconds(500));
  RigCycle cycle(&rig, 1e-3, 2.5e-3);
  std::int64_t cycles = 0;
  while (!StopRequested()) {
    clock.WaitNext();
    const auto start = std::chrono::steady_clock::now();
    const std::int64_t now = UtimeNow();
    DriveImageCommand command{};
    const bool commanded = image.LatestCommand(&command);
    DriveSetpoint setpoint;
    setpoint.utime = command.utime;
    for (int i = 0; i < 6; ++i) {
      setpoint.motor_angle_rad[i] = command.motor_angle_rad[i];
      setpoint.motor_velocity_rad_s[i] = command.motor_velocity_rad_s[i];
    }
    const RigCycleReport report = cycle.Step(now, commanded ? &setpoint : nullptr, command.enable != 0);
    image.PublishFeedback(report.feedback, now, ++cycles);
    truth_out.Publish(report.truth);
    if (report.tracker_due && tracker_out.Publish(report.tracker)) status.CountOut();
    if (commanded) status.CountIn();
    if (report.watchdog_changed) {
      faults.Publish(WatchdogFault(command_segment, rig.watchdog_tripped(), rig.since_command_s(), now));
    }
    if (report.physics_failed) {
      faults.Publish(MakeFault("rig", "", FaultCode::kForwardKinematics, fault_t::SEVERITY_ERROR,
                               "the virtual platform's pose could not be found", now));
      status.SetState(node_status_t::STATE_FAULT);
    }
    status.RecordLoop(std::chrono::steady_clock::now() - start);
    if (status.Due(now)) status_out.Publish(status.Report(now, clock.missed()));
  }
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-rig", edsp::Run, argc, argv); }
