#include "edsp/actuator_bridge/cia402_backend.h"

#include <chrono>
#include <thread>

#include <fmt/format.h>

#include "edsp/drives/csp_master.h"

namespace edsp {
namespace {

constexpr std::int64_t kReconnectEveryUs = 100000;

DriveStatus StatusOf(cia402::State state) {
  switch (state) {
    case cia402::State::kOperationEnabled: return DriveStatus::kEnabled;
    case cia402::State::kFault:
    case cia402::State::kFaultReactionActive: return DriveStatus::kFault;
    default: return DriveStatus::kDisabled;
  }
}

}  // namespace

Cia402Backend::Cia402Backend(const DrivesConfig& config, std::unique_ptr<cia402::CspLink> link)
    : config_(config), link_(std::move(link)) {}

bool Cia402Backend::Configure(const PlatformConfig&, std::string* error) {
  if (!lifecycle_.Allows(BackendTransition::kConfigure, error)) return false;
  if (const std::optional<std::string> problem = ScalingProblem(config_.scaling)) {
    *error = *problem;
    return false;
  }
  return lifecycle_.Take(BackendTransition::kConfigure, error);
}

bool Cia402Backend::Exchange(Enabling enabling, std::string* error) {
  for (std::size_t d = 0; d < commands_.size(); ++d) {
    const cia402::State state = cia402::StateOfStatusword(feedback_[d].statusword);
    cia402::CspCommand& c = commands_[d];
    // A drive in operation holds a fixed target: the bridge's, or where it
    // stood when it entered operation (never its own drifting actual).
    if (state == cia402::State::kOperationEnabled && !target_counts_[d]) {
      target_counts_[d] = feedback_[d].position_actual;
      velocity_counts_[d] = 0;
    }
    const bool faulted = state == cia402::State::kFault || state == cia402::State::kFaultReactionActive;
    const bool may_enable = enabling == Enabling::kResetFaults || (enabling == Enabling::kNotFaulted && !faulted);
    if (state != cia402::State::kOperationEnabled && !may_enable) {
      // Out of operation, and not this call's to bring back (a fault only
      // the operator's re-arm resets; any drive outside an activation):
      // no power, the target where it stands.
      c.controlword = cia402::ControlwordFor(cia402::Command::kDisableVoltage);
      c.mode_of_operation = cia402::kModeCyclicSynchronousPosition;
      c.target_position = feedback_[d].position_actual;
      c.velocity_offset = 0;
      target_counts_[d].reset();
      continue;
    }
    if (state != cia402::State::kOperationEnabled) target_counts_[d].reset();
    c = cia402::NextCspCommand(feedback_[d], c.controlword, target_counts_[d], velocity_counts_[d]);
  }
  return link_->Exchange(commands_, &feedback_, error);
}

bool Cia402Backend::ConnectAndRead(std::string* error) {
  // What the drives are now, read before any command is built on it: after
  // an outage a drive may have stopped, faulted or moved.
  if (!link_->Connect(error)) return false;
  return link_->ReadFeedback(&feedback_, error);
}

bool Cia402Backend::Enabled(Enabling enabling) const {
  for (const cia402::CspFeedback& f : feedback_) {
    const cia402::State s = cia402::StateOfStatusword(f.statusword);
    const bool left_faulted = enabling == Enabling::kNotFaulted && s == cia402::State::kFault;
    if (s != cia402::State::kOperationEnabled && !left_faulted) return false;
  }
  return true;
}

bool Cia402Backend::LatchedSince(const CycleCounts& before) const {
  for (std::size_t d = 0; d < feedback_.size(); ++d) {
    if (feedback_[d].cycle_count == before[d]) return false;
  }
  return true;
}

// Judged only on feedback every drive latched after this call's previous
// exchange (a new cycle count): an older image may still show a state the
// drives have since left (operation enabled, before a deactivation's
// shutdown reached them), and the first cycle would find them out of it.
// The first exchange's answer is never judged: it may show the last
// commands of a predecessor, not this call's.
bool Cia402Backend::EnableDrives(Enabling enabling, std::chrono::milliseconds budget, std::string* error) {
  constexpr int kLatchedCycles = 50;
  const auto give_up = std::chrono::steady_clock::now() + budget;
  if (!Exchange(enabling, error)) return false;
  int latched = 0;
  while (latched < kLatchedCycles && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    CycleCounts before;
    for (std::size_t d = 0; d < feedback_.size(); ++d) before[d] = feedback_[d].cycle_count;
    if (!Exchange(enabling, error)) return false;
    if (LatchedSince(before)) {
      if (Enabled(enabling)) return true;
      ++latched;
    }
  }
  if (latched == 0) {
    *error = fmt::format(
        "{}: the drives latched no new feedback in {} ms of enabling (cycle count stays {}): "
        "they are not cycling",
        link_->endpoint(), budget.count(), feedback_[0].cycle_count);
    return false;
  }
  for (std::size_t d = 0; d < feedback_.size(); ++d) {
    const cia402::State s = cia402::StateOfStatusword(feedback_[d].statusword);
    if (s != cia402::State::kOperationEnabled) {
      *error = fmt::format("{}: drive {} stays in {} (error code {:04X}h) after {} of its cycles of enabling",
                           link_->endpoint(), d + 1, cia402::StateName(s), feedback_[d].error_code, latched);
      break;
    }
  }
  return false;
}

bool Cia402Backend::Activate(std::string* error) {
  if (!lifecycle_.Allows(BackendTransition::kActivate, error)) return false;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!ConnectAndRead(error)) {
    if (std::chrono::steady_clock::now() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  target_counts_.fill(std::nullopt);
  // Start-up enables the drives where they stand but resets no fault: a
  // drive found in fault (a predecessor's outage) stays so, the first
  // cycle fails on it, and the bridge holds until the operator re-arms.
  if (!EnableDrives(Enabling::kNotFaulted, kActivateBudget, error)) {
    PowerDown();  // those it did enable: inactive means without power
    link_->Disconnect();
    return false;
  }
  lifecycle_.Take(BackendTransition::kActivate);
  detail_.clear();
  fault_cause_.clear();
  return true;
}

bool Cia402Backend::Reset(std::string* error) {
  if (!lifecycle_.Allows(BackendTransition::kRecover, error)) return false;
  if (!link_->connected() && !ConnectAndRead(error)) return false;
  // Only the drives out of operation are reset and enabled (where they
  // stand); the others keep power and their targets throughout.
  if (!EnableDrives(Enabling::kResetFaults, kReArmBudget, error)) return false;
  lifecycle_.Take(BackendTransition::kRecover);
  detail_.clear();
  fault_cause_.clear();
  return true;
}

void Cia402Backend::PowerDown() {
  if (!link_->connected()) return;
  for (cia402::CspCommand& c : commands_) c.controlword = cia402::ControlwordFor(cia402::Command::kShutdown);
  std::string ignored;
  link_->Exchange(commands_, &feedback_, &ignored);
}

void Cia402Backend::Deactivate() {
  if (!lifecycle_.Allows(BackendTransition::kDeactivate)) return;  // not cycling: nothing to stop
  PowerDown();
  lifecycle_.Take(BackendTransition::kDeactivate);
}

void Cia402Backend::Cleanup() {
  if (lifecycle_.Take(BackendTransition::kCleanup)) link_->Disconnect();
}

void Cia402Backend::Fail(const std::string& why) {
  detail_ = why;
  if (lifecycle_.state() == BackendState::kActive) fault_cause_ = why;
  lifecycle_.Take(BackendTransition::kError);
}

// The cycle's one request: this setpoint out, the drives' answer in (kept
// for the next cycle's Read, as a fieldbus master's inputs are).
bool Cia402Backend::Write(std::int64_t now_utime, const DriveSetpoint& setpoint) {
  const BackendState state = lifecycle_.state();
  if (state != BackendState::kActive && state != BackendState::kFault) return false;  // not cycling
  std::array<std::optional<std::int32_t>, 6> targets;
  std::array<std::int32_t, 6> velocities{};
  std::string unfit;
  for (std::size_t d = 0; d < 6 && unfit.empty(); ++d) {
    targets[d] = config_.scaling[d].ToCounts(setpoint.motor_angle_rad[d]);
    const auto v = config_.scaling[d].ToCountsPerSecond(setpoint.motor_velocity_rad_s[d]);
    if (!targets[d] || !v) {
      unfit = fmt::format("leg {}: motor angle {} rad does not fit the drive's counts: not sent", d + 1,
                          setpoint.motor_angle_rad[d]);
    } else {
      velocities[d] = *v;
    }
  }
  if (state == BackendState::kFault) {
    // Motion only while active: the drives hold the last target taken, at rest.
    velocity_counts_.fill(0);
  } else if (unfit.empty()) {  // else the previous targets stay in force, and still go out
    target_counts_ = targets;
    velocity_counts_ = velocities;
  }
  if (!link_->connected()) return false;  // Read reconnects
  std::string error;
  if (!Exchange(Enabling::kNone, &error)) {
    Fail(error);
    last_connect_utime_ = now_utime;
    return false;
  }
  DriveFeedback answer;
  Describe(&answer);
  if (!unfit.empty()) detail_ = detail_.empty() ? unfit : unfit + "; " + detail_;
  return detail_.empty() && lifecycle_.state() == BackendState::kActive;
}

// The drives' answer to the last cycle's request (or, after a reconnect, to
// a read that wrote nothing).
bool Cia402Backend::Read(std::int64_t now_utime, DriveFeedback* feedback) {
  const BackendState state = lifecycle_.state();
  if (state != BackendState::kActive && state != BackendState::kFault) {  // not cycling: no reconnect
    Describe(feedback);
    return false;
  }
  if (!link_->connected()) {
    if (last_connect_utime_ >= 0 && now_utime - last_connect_utime_ < kReconnectEveryUs) {
      Describe(feedback);
      return false;
    }
    last_connect_utime_ = now_utime;
    std::string error;
    if (!ConnectAndRead(&error)) {
      Fail(error);
      Describe(feedback);
      return false;
    }
  }
  Describe(feedback);
  return detail_.empty() && lifecycle_.state() == BackendState::kActive;
}

void Cia402Backend::Describe(DriveFeedback* feedback) {
  const bool cycling = lifecycle_.state() == BackendState::kActive || lifecycle_.state() == BackendState::kFault;
  std::string faults;
  for (std::size_t d = 0; d < 6; ++d) {
    const cia402::State s = cia402::StateOfStatusword(feedback_[d].statusword);
    feedback->motor_angle_rad[d] = config_.scaling[d].ToAngle(feedback_[d].position_actual);
    feedback->motor_velocity_rad_s[d] = config_.scaling[d].ToRate(feedback_[d].velocity_actual);
    feedback->status[d] = link_->connected() ? StatusOf(s) : DriveStatus::kDisabled;
    if (link_->connected() && cycling && s != cia402::State::kOperationEnabled) {
      faults += fmt::format("{}drive {} in {} (error code {:04X}h)", faults.empty() ? "" : "; ", d + 1,
                            cia402::StateName(s), feedback_[d].error_code);
    }
  }
  if (!link_->connected() || !cycling) return;
  if (!faults.empty()) {
    Fail(faults);
  } else if (lifecycle_.state() == BackendState::kFault) {
    detail_ = "every drive answers and is in operation; in fault until re-armed (since: " + fault_cause_ + ")";
  } else {
    detail_.clear();
  }
}

}  // namespace edsp
