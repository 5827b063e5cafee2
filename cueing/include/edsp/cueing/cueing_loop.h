#pragma once
// edsp-cueing live on a bus: at each tick the vehicle's samples (a UDP
// socket's packets, or EDSP_VEHICLE's messages) through CueingSource, its cue out on EDSP_CUE_SETPOINT, and its
// requests to the planner (engage, disengage, stop) on EDSP_MOTION_REQUEST,
// sent again until answered without ever blocking the cycle. The planner's
// EDSP_MOTION_STATUS says whether its setpoints follow this source. Every
// packet refused is an EDSP_FAULT naming why; EDSP_STATUS once a second.
// The socket's samples that the source took go out on EDSP_VEHICLE too,
// stamped at the cycle that took them, so that a run fed over UDP is
// logged and scored (edsp-cueing score) as one fed on the bus.

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <string>

#include "edsp/cueing/cueing_source.h"
#include "edsp/cueing/vehicle_packet.h"
#include "edsp/cueing/vehicle_socket.h"
#include "edsp/motion_status_t.hpp"
#include "edsp/node/node_reporting.h"
#include "edsp/node/request_client.h"
#include "edsp/node/runtime.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/transport/bus.h"
#include "edsp/vehicle_motion_t.hpp"

namespace edsp {

// Just before the planner's tick (phase 0): a cue is at most 0.2 ms old when followed.
inline constexpr std::chrono::microseconds kCueingPhase{800};

struct CueingLoopOptions {
  std::int64_t session_id = 1;
  std::string client = "edsp-cueing";  // the planner's status names the source by it
  std::string input_name;              // the samples' origin in faults ("UDP 127.0.0.1:7400", "EDSP_VEHICLE")
  bool vehicle_on_bus = false;         // the samples on EDSP_VEHICLE (else the socket's, if any)
  double answer_timeout_s = 5.0;       // a request unanswered this long counts as refused
};

class CueingLoop {
 public:
  // Set-up: advertises and subscribes on `bus` (may throw TransportError).
  // The vehicle's samples come from `socket` (if any) and from EDSP_VEHICLE
  // if the options say so. The bus, the source and the socket must outlive the loop.
  CueingLoop(Bus& bus, CueingSource& source, VehicleSocket* socket, CueingLoopOptions options);

  // One cycle at `now`: the samples that came, the source's step, its cue and request.
  bool RunCycle(std::int64_t now_utime, std::int64_t deadline_misses);
  void Run(CycleClock& clock, const std::function<bool()>& stop);

 private:
  void OnVehicleMessage(const vehicle_motion_t& message);
  // `what`: "vehicle packet" or "vehicle message", as the fault says. True
  // if the source took the sample.
  bool TakeSample(const ParsedVehiclePacket& parsed, const char* what, std::int64_t now_utime);
  void TakePackets(std::int64_t now_utime);
  void TakeVehicleMessages(std::int64_t now_utime);
  void Ask(CueRequest request);
  void TakeAnswer(std::int64_t now_utime);
  void Publish(const CueSetpoint& cue, std::int64_t utime, std::uint32_t input_sequence);
  void OnStatus(const motion_status_t& status);

  Bus& bus_;
  CueingSource& source_;
  VehicleSocket* socket_;
  CueingLoopOptions options_;
  Bus::Publisher<pose_setpoint_t> cues_;
  std::optional<Bus::Publisher<vehicle_motion_t>> vehicle_out_;  // the socket's samples taken, on the bus
  NodeReporting reporting_;
  RequestClient requests_;
  // EDSP_VEHICLE's messages since the last cycle, taken at its start as
  // the socket's are; at most a second of a 1 kHz host's (the rest dropped, said).
  std::deque<vehicle_motion_t> vehicle_messages_;
  std::uint64_t vehicle_messages_dropped_ = 0;
  std::optional<CueRequest> in_flight_;
  std::int64_t engage_id_ = 0;  // the last engage's request id: the planner's status names it while it follows
  std::chrono::steady_clock::time_point asked_at_;
  std::int64_t cue_seq_ = 0;
};

}  // namespace edsp
