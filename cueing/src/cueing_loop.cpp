#include "edsp/cueing/cueing_loop.h"

#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/cueing/vehicle_message.h"
#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_request_t.hpp"
#include "edsp/node/fault.h"
#include "edsp/node/node_loop.h"
#include "edsp/node/request_service.h"

namespace edsp {

namespace {

std::int8_t KindOf(CueRequest request) {
  switch (request) {
    case CueRequest::kEngage: return motion_request_t::KIND_ENGAGE;
    case CueRequest::kDisengage: return motion_request_t::KIND_DISENGAGE;
    case CueRequest::kStop: return motion_request_t::KIND_STOP;
  }
  return motion_request_t::KIND_STOP;
}

constexpr std::size_t kMaxQueuedVehicleMessages = 1000;
const double kStampWindow_s = RequestPolicy{}.window_s;

}  // namespace

CueingLoop::CueingLoop(Bus& bus, CueingSource& source, VehicleSocket* socket, CueingLoopOptions options)
    : bus_(bus),
      source_(source),
      socket_(socket),
      options_(std::move(options)),
      cues_(bus.Advertise<pose_setpoint_t>(channel::kCueSetpoint)),
      reporting_(bus, "cueing"),
      requests_(bus) {
  bus.Subscribe<motion_status_t>(channel::kMotionStatus, [this](const motion_status_t& s) { OnStatus(s); });
  if (options_.vehicle_on_bus) {
    bus.Subscribe<vehicle_motion_t>(channel::kVehicle, [this](const vehicle_motion_t& m) { OnVehicleMessage(m); });
    reporting_.WatchInput(bus, channel::kVehicle);
  } else if (socket_ != nullptr) {
    vehicle_out_.emplace(bus.Advertise<vehicle_motion_t>(channel::kVehicle));
  }
}

void CueingLoop::OnVehicleMessage(const vehicle_motion_t& message) {
  if (vehicle_messages_.size() >= kMaxQueuedVehicleMessages) {
    ++vehicle_messages_dropped_;
    return;
  }
  vehicle_messages_.push_back(message);
}

void CueingLoop::OnStatus(const motion_status_t& status) {
  if (status.session_id != options_.session_id) return;
  const bool follows =
      status.state == motion_status_t::STATE_CUEING && engage_id_ != 0 && status.request_id == engage_id_;
  source_.OnPlannerFollows(follows, status.reason);
}

bool CueingLoop::TakeSample(const ParsedVehiclePacket& parsed, const char* what, std::int64_t now_utime) {
  std::optional<std::string> refused;
  FaultCode code = FaultCode::kUndecodable;
  if (!parsed.packet) {
    refused = parsed.error;
  } else {
    refused = source_.OnPacket(*parsed.packet, static_cast<double>(now_utime) * 1e-6);
    code = FaultCode::kStale;
  }
  if (!refused) {
    reporting_.status().CountIn();
    return true;
  }
  reporting_.status().CountRejected();
  reporting_.Fault(MakeFault("cueing", options_.input_name, code, fault_t::SEVERITY_WARNING,
                             std::string(what) + " refused: " + *refused, now_utime));
  return false;
}

void CueingLoop::TakePackets(std::int64_t now_utime) {
  socket_->Drain([&](const std::uint8_t* data, std::size_t size) {
    const ParsedVehiclePacket parsed = ParseVehiclePacket(data, size);
    if (TakeSample(parsed, "vehicle packet", now_utime) && vehicle_out_) {
      vehicle_out_->Publish(VehicleMessage(*parsed.packet, options_.session_id, now_utime));
    }
  });
}

void CueingLoop::TakeVehicleMessages(std::int64_t now_utime) {
  for (; !vehicle_messages_.empty(); vehicle_messages_.pop_front()) {
    const vehicle_motion_t& message = vehicle_messages_.front();
    if (message.session_id != options_.session_id) {
      // Another group's host, or a log of another session replayed: never cued.
      reporting_.status().CountRejected();
      reporting_.Fault(MakeFault("cueing", channel::kVehicle, FaultCode::kForeignSession, fault_t::SEVERITY_WARNING,
                                 "vehicle message of session " + std::to_string(message.session_id) +
                                     " refused: this group's is " + std::to_string(options_.session_id),
                                 now_utime));
      continue;
    }
    // A log of this session replayed later (a fixed session id), or a host
    // whose clock is off: stamped further from this node's clock than a
    // request may be (request_service.h), never cued.
    const double age_s = static_cast<double>(now_utime - message.utime) * 1e-6;
    if (!(std::abs(age_s) <= kStampWindow_s)) {
      reporting_.status().CountRejected();
      reporting_.Fault(MakeFault(
          "cueing", channel::kVehicle, FaultCode::kStale, fault_t::SEVERITY_WARNING,
          fmt::format("vehicle message seq {} stamped {:.1f} s {} this node's clock refused (a replayed log, or a "
                      "clock off by more than {} s)",
                      message.seq, std::abs(age_s), age_s > 0 ? "before" : "after", kStampWindow_s),
          now_utime));
      continue;
    }
    TakeSample(ReadVehicleMessage(message), "vehicle message", now_utime);
  }
  if (vehicle_messages_dropped_ > 0) {
    reporting_.Fault(MakeFault("cueing", channel::kVehicle, FaultCode::kTransport, fault_t::SEVERITY_WARNING,
                               std::to_string(vehicle_messages_dropped_) + " vehicle messages dropped: more than " +
                                   std::to_string(kMaxQueuedVehicleMessages) + " came within one cycle",
                               now_utime));
    vehicle_messages_dropped_ = 0;
  }
}

void CueingLoop::Ask(CueRequest request) {
  motion_request_t r{};
  r.session_id = options_.session_id;
  r.request_id = RequestClient::NewRequestId();
  r.client = options_.client;
  r.kind = KindOf(request);
  for (int k = 0; k < 6; ++k) r.pose[k] = source_.neutral_pose()(k);
  if (request == CueRequest::kEngage) engage_id_ = r.request_id;
  requests_.Start<motion_reply_t>(channel::kMotionRequest, channel::kMotionReply, r);
  in_flight_ = request;
  asked_at_ = std::chrono::steady_clock::now();
}

void CueingLoop::TakeAnswer(std::int64_t now_utime) {
  if (!in_flight_) return;
  requests_.ResendIfDue();
  const std::optional<motion_reply_t>& reply = requests_.Answer<motion_reply_t>(channel::kMotionReply);
  if (reply) {
    source_.OnReply(*in_flight_, reply->accepted, reply->reason);
    in_flight_.reset();
    return;
  }
  const double waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - asked_at_).count();
  if (waited_s < options_.answer_timeout_s) return;
  const std::string why = "no reply from the planner within " + std::to_string(options_.answer_timeout_s) + " s";
  reporting_.Fault(
      MakeFault("cueing", channel::kMotionRequest, FaultCode::kStale, fault_t::SEVERITY_ERROR, why, now_utime));
  source_.OnReply(*in_flight_, false, why);
  in_flight_.reset();
}

void CueingLoop::Publish(const CueSetpoint& cue, std::int64_t utime, std::uint32_t input_sequence) {
  pose_setpoint_t sp{};
  sp.utime = utime;
  sp.seq = ++cue_seq_;
  sp.session_id = options_.session_id;
  for (int k = 0; k < 6; ++k) {
    sp.pose[k] = cue.pose(k);
    sp.velocity[k] = cue.velocity(k);
    sp.acceleration[k] = cue.acceleration(k);
  }
  sp.trajectory = "cueing";
  sp.phase = pose_setpoint_t::PHASE_CUEING;
  sp.segment = VehicleSequenceAsSegment(input_sequence);
  if (cues_.Publish(sp)) reporting_.status().CountOut();
}

bool CueingLoop::RunCycle(std::int64_t now_utime, std::int64_t deadline_misses) {
  const auto began = std::chrono::steady_clock::now();
  if (socket_ != nullptr) TakePackets(now_utime);
  if (options_.vehicle_on_bus) TakeVehicleMessages(now_utime);
  TakeAnswer(now_utime);
  const CueingStep step = source_.Step(static_cast<double>(now_utime) * 1e-6);
  if (step.cue) Publish(*step.cue, std::llround(step.time_s * 1e6), step.input_sequence);
  if (step.request) Ask(*step.request);
  reporting_.status().SetState(source_.phase() == CueingPhase::kStopped ? node_status_t::STATE_HOLDING
                                                                        : node_status_t::STATE_RUNNING);
  reporting_.EndCycle(began, now_utime, deadline_misses);
  return true;
}

void CueingLoop::Run(CycleClock& clock, const std::function<bool()>& stop) {
  RunOnClock(bus_, clock, stop, [this](std::int64_t now, std::int64_t missed) { return RunCycle(now, missed); });
}

}  // namespace edsp
