#include "edsp/node/fault.h"

namespace edsp {

const char* FaultCodeName(FaultCode code) {
  switch (code) {
    case FaultCode::kNonFinite: return "non-finite";
    case FaultCode::kOutsideWorkspace: return "outside workspace";
    case FaultCode::kForeignSession: return "foreign session";
    case FaultCode::kStale: return "stale";
    case FaultCode::kUndecodable: return "undecodable";
    case FaultCode::kJump: return "jump";
    case FaultCode::kOutOfStroke: return "out of stroke";
    case FaultCode::kForwardKinematics: return "forward kinematics";
    case FaultCode::kBackend: return "drive backend";
  }
  return "unknown";
}

fault_t MakeFault(const std::string& node, const std::string& channel, FaultCode code,
                  std::int8_t severity, std::string reason, std::int64_t utime) {
  fault_t fault{};
  fault.utime = utime;
  fault.node = node;
  fault.channel = channel;
  fault.severity = severity;
  fault.code = static_cast<std::int32_t>(code);
  fault.reason = std::move(reason);
  return fault;
}

}  // namespace edsp
