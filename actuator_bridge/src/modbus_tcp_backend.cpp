#include "edsp/actuator_bridge/modbus_tcp_backend.h"

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

ModbusTcpBackend::ModbusTcpBackend(const DrivesConfig& config)
    : config_(config), master_(config.host, config.port, config.response_timeout_s) {}

bool ModbusTcpBackend::Configure(const PlatformConfig&, std::string* error) {
  for (std::size_t i = 0; i < config_.scaling.size(); ++i) {
    const std::string problem = config_.scaling[i].Problem();
    if (!problem.empty()) {
      *error = fmt::format("[drives] leg {}: {}", i + 1, problem);
      state_ = BackendState::kFault;
      return false;
    }
  }
  state_ = BackendState::kInactive;
  return true;
}

bool ModbusTcpBackend::Exchange(bool enabling, std::string* error) {
  for (std::size_t d = 0; d < commands_.size(); ++d) {
    const cia402::State state = cia402::StateOfStatusword(feedback_[d].statusword);
    cia402::CspCommand& c = commands_[d];
    if (!have_feedback_ || (!enabling && state != cia402::State::kOperationEnabled)) {
      // Nothing known yet, or a drive that left operation (a fault, a
      // quick stop): only an activation (the operator's re-arm) brings it
      // back; until then no power, the target where it stands.
      c.controlword = cia402::ControlwordFor(cia402::Command::kDisableVoltage);
      c.mode_of_operation = cia402::kModeCyclicSynchronousPosition;
      c.target_position = feedback_[d].position_actual;
      c.velocity_offset = 0;
      continue;
    }
    c = cia402::NextCspCommand(feedback_[d], c.controlword, enabling ? std::nullopt : target_counts_[d],
                               velocity_counts_[d]);
  }
  if (!master_.Exchange(commands_, &feedback_, error)) return false;
  have_feedback_ = true;
  return true;
}

bool ModbusTcpBackend::Activate(std::string* error) {
  if (state_ != BackendState::kInactive) {
    *error = "activate needs a configured, inactive backend";
    return false;
  }
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!master_.connected() && !master_.Connect(error)) {
    if (std::chrono::steady_clock::now() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  target_counts_.fill(std::nullopt);
  have_feedback_ = false;
  // Enable every drive where it stands: a few cycles of the state machine
  // (a faulted drive is reset here, by this activation, and only here).
  for (int cycle = 0; cycle < 50; ++cycle) {
    if (!Exchange(true, error)) return false;
    bool all = true;
    for (const cia402::CspFeedback& f : feedback_) {
      all = all && cia402::StateOfStatusword(f.statusword) == cia402::State::kOperationEnabled;
    }
    if (all) {
      state_ = BackendState::kActive;
      detail_.clear();
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  for (std::size_t d = 0; d < feedback_.size(); ++d) {
    const cia402::State s = cia402::StateOfStatusword(feedback_[d].statusword);
    if (s != cia402::State::kOperationEnabled) {
      *error = fmt::format("{}: drive {} stays in {} (error code {:04X}h) after 50 cycles of enabling",
                           master_.endpoint(), d + 1, cia402::StateName(s), feedback_[d].error_code);
      break;
    }
  }
  return false;
}

void ModbusTcpBackend::Deactivate() {
  if (master_.connected()) {
    for (cia402::CspCommand& c : commands_) c.controlword = cia402::ControlwordFor(cia402::Command::kShutdown);
    std::string ignored;
    master_.Exchange(commands_, &feedback_, &ignored);
  }
  state_ = BackendState::kInactive;
}

bool ModbusTcpBackend::Write(std::int64_t, const DriveSetpoint& setpoint) {
  if (state_ != BackendState::kActive) return false;  // motion only while active
  std::array<std::optional<std::int32_t>, 6> targets;
  std::array<std::int32_t, 6> velocities{};
  for (std::size_t d = 0; d < 6; ++d) {
    targets[d] = config_.scaling[d].ToCounts(setpoint.motor_angle_rad[d]);
    const auto v = config_.scaling[d].ToCountsPerSecond(setpoint.motor_velocity_rad_s[d]);
    if (!targets[d] || !v) {
      detail_ = fmt::format("leg {}: motor angle {} rad does not fit the drive's counts: not sent", d + 1,
                            setpoint.motor_angle_rad[d]);
      return false;  // the previous targets stay in force
    }
    velocities[d] = *v;
  }
  target_counts_ = targets;
  velocity_counts_ = velocities;
  return true;
}

bool ModbusTcpBackend::Read(std::int64_t now_utime, DriveFeedback* feedback) {
  if (!master_.connected()) {
    if (last_connect_utime_ >= 0 && now_utime - last_connect_utime_ < kReconnectEveryUs) {
      Describe(feedback);
      return false;
    }
    last_connect_utime_ = now_utime;
    std::string error;
    if (!master_.Connect(&error)) {
      detail_ = error;
      Describe(feedback);
      return false;
    }
  }
  std::string error;
  if (!Exchange(false, &error)) {
    detail_ = error;
    last_connect_utime_ = now_utime;
    Describe(feedback);
    return false;
  }
  Describe(feedback);
  return detail_.empty();
}

bool ModbusTcpBackend::Reset(std::string* error) {
  Deactivate();
  return Activate(error);
}

void ModbusTcpBackend::Describe(DriveFeedback* feedback) {
  std::string faults;
  for (std::size_t d = 0; d < 6; ++d) {
    const cia402::State s = cia402::StateOfStatusword(feedback_[d].statusword);
    feedback->motor_angle_rad[d] = config_.scaling[d].ToAngle(feedback_[d].position_actual);
    feedback->motor_velocity_rad_s[d] = config_.scaling[d].ToRate(feedback_[d].velocity_actual);
    feedback->status[d] = master_.connected() ? StatusOf(s) : DriveStatus::kDisabled;
    if (master_.connected() && state_ == BackendState::kActive && s != cia402::State::kOperationEnabled) {
      faults += fmt::format("{}drive {} in {} (error code {:04X}h)", faults.empty() ? "" : "; ", d + 1,
                            cia402::StateName(s), feedback_[d].error_code);
    }
  }
  if (master_.connected()) detail_ = faults;
}

}  // namespace edsp
