#include "edsp/rig/rig_loop.h"

#include <cstdio>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/node/fault.h"
#include "edsp/node/node_loop.h"

namespace edsp {

namespace {

fault_t WatchdogFault(const std::string& segment, bool tripped, double since_command_s, std::int64_t now) {
  if (tripped) {
    return MakeFault("rig", segment, FaultCode::kStale, fault_t::SEVERITY_ERROR,
                     fmt::format("drive watchdog: no drive command for {:.1f} ms; the drives hold "
                                 "their position",
                                 since_command_s * 1e3),
                     now);
  }
  return MakeFault("rig", segment, FaultCode::kStale, fault_t::SEVERITY_INFO,
                   "drive watchdog: drive commands again; the drives follow them", now);
}

DriveSetpoint SetpointOf(const DriveImageCommand& command) {
  DriveSetpoint setpoint;
  setpoint.utime = command.utime;
  for (int i = 0; i < 6; ++i) {
    setpoint.motor_angle_rad[i] = command.motor_angle_rad[i];
    setpoint.motor_velocity_rad_s[i] = command.motor_velocity_rad_s[i];
  }
  return setpoint;
}

}  // namespace

RigLoop::RigLoop(Bus& bus, VirtualRig& rig, DriveImageServer& image, const ImageRestore& restore)
    : rig_(rig),
      image_(image),
      cycle_(&rig, std::chrono::duration<double>(kRigPeriod).count(), kRigCommandHorizon_s, kRigLongestCatchUp),
      tracker_out_(bus.Advertise<tracker_point_t>(channel::kTracker)),
      truth_out_(bus.Advertise<rig_truth_t>(channel::kRigTruth)),
      reporting_(bus, "rig") {
  image_commands_.reserve(16);  // what the command ring holds
  commands_.reserve(16);
  if (!restore.note.empty()) {
    std::fprintf(stderr, "edsp-rig: %s\n", restore.note.c_str());
    reporting_.Fault(MakeFault("rig", image.feedback_segment(), FaultCode::kProcess,
                               restore.restored ? fault_t::SEVERITY_INFO : fault_t::SEVERITY_WARNING, restore.note,
                               UtimeNow()));
  }
}

void RigLoop::RunCycle(std::int64_t now, std::int64_t deadline_misses) {
  const auto start = std::chrono::steady_clock::now();
  image_commands_.clear();
  image_.NewCommands(&image_commands_);
  commands_.clear();
  for (const DriveImageCommand& c : image_commands_) commands_.push_back(DriveCommand{SetpointOf(c), c.enable != 0});
  reporting_.status().CountIn(static_cast<std::int64_t>(commands_.size()));
  const std::vector<RigCycleReport>& reports = cycle_.Wake(now, commands_);
  for (const RigCycleReport& report : reports) Publish(report);
  if (!reports.empty()) {  // none while the rig waits for its controller to catch up
    cycles_ += static_cast<std::int64_t>(reports.size());
    image_.PublishFeedback(reports.back().feedback, reports.back().utime, cycles_);
  }
  reporting_.EndCycle(start, now, deadline_misses);
}

void RigLoop::Publish(const RigCycleReport& report) {
  truth_out_.Publish(report.truth);
  if (report.tracker_due && tracker_out_.Publish(report.tracker)) reporting_.status().CountOut();
  if (report.watchdog_changed) {
    reporting_.Fault(
        WatchdogFault(image_.command_segment(), report.watchdog_tripped, report.since_command_s, report.utime));
  }
  if (report.physics_failed) {
    reporting_.Fault(MakeFault("rig", "", FaultCode::kForwardKinematics, fault_t::SEVERITY_ERROR,
                               "the virtual platform's pose could not be found", report.utime));
    reporting_.status().SetState(node_status_t::STATE_FAULT);
  }
}

void RigLoop::Run(CycleClock& clock, const std::function<bool()>& stop) {
  RunOnClock(clock, stop, [this](std::int64_t now, std::int64_t missed) {
    RunCycle(now, missed);
    return true;
  });
}

}  // namespace edsp
