#pragma once
// edsp-cueing live on a bus: at each tick the vehicle's packets (a UDP
// socket) through CueingSource, its cue out on EDSP_CUE_SETPOINT, and its
// requests to the planner (engage, disengage, stop) on EDSP_MOTION_REQUEST,
// sent again until answered without ever blocking the cycle. The planner's
// EDSP_MOTION_STATUS says whether its setpoints follow this source. Every
// packet refused is an EDSP_FAULT naming why; EDSP_STATUS once a second.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "edsp/cueing/cueing_source.h"
#include "edsp/cueing/vehicle_socket.h"
#include "edsp/motion_status_t.hpp"
#include "edsp/node/node_reporting.h"
#include "edsp/node/request_client.h"
#include "edsp/node/runtime.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/transport/bus.h"

namespace edsp {

// Just before the planner's tick (phase 0): a cue is at most 0.2 ms old when followed.
inline constexpr std::chrono::microseconds kCueingPhase{800};

struct CueingLoopOptions {
  std::int64_t session_id = 1;
  std::string client = "edsp-cueing";  // the planner's status names the source by it
  std::string input_name;              // the packets' origin in faults ("UDP 127.0.0.1:7400")
  double answer_timeout_s = 5.0;       // a request unanswered this long counts as refused
};

class CueingLoop {
 public:
  // Set-up: advertises and subscribes on `bus` (may throw TransportError).
  // The bus, the source and the socket (if any) must outlive the loop.
  CueingLoop(Bus& bus, CueingSource& source, VehicleSocket* socket, CueingLoopOptions options);

  // One cycle at `now`: the packets that came, the source's step, its cue and request.
  bool RunCycle(std::int64_t now_utime, std::int64_t deadline_misses);
  void Run(CycleClock& clock, const std::function<bool()>& stop);

 private:
  void TakePacket(const std::uint8_t* data, std::size_t size, std::int64_t now_utime);
  void Ask(CueRequest request);
  void TakeAnswer(std::int64_t now_utime);
  void Publish(const CueSetpoint& cue, std::int64_t utime, std::uint32_t input_sequence);
  void OnStatus(const motion_status_t& status);

  Bus& bus_;
  CueingSource& source_;
  VehicleSocket* socket_;
  CueingLoopOptions options_;
  Bus::Publisher<pose_setpoint_t> cues_;
  NodeReporting reporting_;
  RequestClient requests_;
  std::optional<CueRequest> in_flight_;
  std::int64_t engage_id_ = 0;  // the last engage's request id: the planner's status names it while it follows
  std::chrono::steady_clock::time_point asked_at_;
  std::int64_t cue_seq_ = 0;
};

}  // namespace edsp
