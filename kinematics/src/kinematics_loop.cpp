#include "edsp/kinematics/kinematics_loop.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "edsp/channels.h"
#include "edsp/node/node_loop.h"
#include "edsp/node/runtime.h"

namespace edsp {

namespace {
constexpr std::int64_t kConfigPeriod_us = 1000000;
constexpr auto kPollInterval = std::chrono::milliseconds(100);
}  // namespace

KinematicsLoop::KinematicsLoop(Bus& bus, KinematicsNode& kinematics, KinematicsLoopOptions options)
    : bus_(bus),
      kinematics_(kinematics),
      options_(std::move(options)),
      commands_(bus.Advertise<leg_command_t>(channel::kLegCommand)),
      states_(bus.Advertise<platform_state_t>(channel::kPlatformState)),
      config_out_(bus.Advertise<platform_config_t>(channel::kConfig)),
      replies_(bus.Advertise<reply_t>(channel::kReply)),
      reporting_(bus, "kinematics") {
  reporting_.WatchInput(bus, channel::kSetpoint, InputLosses::kCountedAsDrops);
  reporting_.WatchInput(bus, channel::kLegState);
  if (options_.leg_state_decimation < 1) {
    throw std::invalid_argument("leg_state_decimation " + std::to_string(options_.leg_state_decimation) +
                                ": one platform state per N >= 1 leg states");
  }
  bus.Subscribe<pose_setpoint_t>(channel::kSetpoint, [this](const pose_setpoint_t& sp) { OnSetpoint(sp); });
  // Replayed from a log, a request is judged by its own clock, as setpoints
  // are: the switches the operator made then are made again.
  bus.Subscribe<pr_mode_t>(channel::kPrMode, [this](const pr_mode_t& request) {
    Answer(kinematics_.HandlePrModeRequest(request, options_.replay ? request.utime : UtimeNow()));
  });
  bus.Subscribe<calibration_t>(channel::kCalibration, [this](const calibration_t& request) {
    Answer(kinematics_.HandleCalibrationRequest(request, options_.replay ? request.utime : UtimeNow()));
  });
  bus.Subscribe<leg_state_t>(channel::kLegState, [this](const leg_state_t& legs) { OnLegState(legs); });
  ReportCalibration();
}

void KinematicsLoop::Answer(const RequestService<reply_t>::Answer& answer) {
  if (answer.acted && answer.reply.code == reply_t::CODE_DONE) {
    std::fprintf(stderr, "edsp-kinematics: %s\n", answer.reply.reason.c_str());
  }
  replies_.Publish(answer.reply);
}

void KinematicsLoop::OnSetpoint(const pose_setpoint_t& setpoint) {
  const auto start = std::chrono::steady_clock::now();
  NodeStatus& status = reporting_.status();
  status.CountIn();
  leg_command_t command;
  fault_t fault;
  const std::int64_t now = options_.replay ? setpoint.utime : UtimeNow();
  if (kinematics_.HandleSetpoint(setpoint, now, &command, &fault)) {
    if (commands_.Publish(command)) status.CountOut();
  } else {
    status.CountRejected();
    reporting_.Fault(fault);
  }
  status.RecordLoop(std::chrono::steady_clock::now() - start);
}

void KinematicsLoop::OnLegState(const leg_state_t& legs) {
  reporting_.status().CountIn();
  kinematics_.NoteDrives(legs);
  if (++leg_states_ % options_.leg_state_decimation != 0) return;
  platform_state_t state;
  fault_t fault;
  if (kinematics_.HandleLegState(legs, UtimeNow(), &state, &fault)) {
    states_.Publish(state);
  } else {
    reporting_.Fault(fault);
  }
}

void KinematicsLoop::ReportCalibration() {
  const calibration::CalibrationModel* c = kinematics_.calibration();
  if (c == nullptr) return;
  std::fprintf(stderr, "edsp-kinematics: calibration %s\n", c->Describe().c_str());
  reporting_.Fault(MakeFault("kinematics", "", FaultCode::kCalibration, fault_t::SEVERITY_INFO,
                             "calibration " + c->Describe(), UtimeNow()));
}

void KinematicsLoop::Poll(std::int64_t now) {
  if (now >= next_config_utime_) {
    config_out_.Publish(kinematics_.ConfigMessage(now, options_.config_text));
    next_config_utime_ = now + kConfigPeriod_us;
  }
  reporting_.StatusTick(now, 0);
}

void KinematicsLoop::Run(const std::function<bool()>& stop) {
  RunPolled(bus_, kPollInterval, stop, [this](std::int64_t now) { Poll(now); });
}

}  // namespace edsp
