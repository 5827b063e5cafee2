#include "edsp/node/fault.h"

#include <algorithm>
#include <cstdlib>

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
    case FaultCode::kBadRequest: return "bad request";
    case FaultCode::kOperatorAction: return "operator action";
    case FaultCode::kStorage: return "storage";
    case FaultCode::kProcess: return "process";
    case FaultCode::kCalibration: return "calibration";
    case FaultCode::kTransport: return "transport";
    case FaultCode::kLatched: return "latched";
  }
  return "unknown";
}

std::optional<FaultCode> FaultCodeFromText(const std::string& text) {
  // Codes are small and dense; a name past the last is "unknown".
  constexpr int kCodesToTry = 64;
  const auto spaced = [](std::string name) {
    std::replace_if(
        name.begin(), name.end(), [](char c) { return c == '_' || c == '-'; }, ' ');
    return name;
  };
  char* end = nullptr;
  const long number = std::strtol(text.c_str(), &end, 10);
  const bool is_number = !text.empty() && *end == '\0';
  for (int c = 1; c < kCodesToTry; ++c) {
    const auto code = static_cast<FaultCode>(c);
    const std::string name = FaultCodeName(code);
    if (name == "unknown") continue;
    if ((is_number && number == c) || spaced(text) == spaced(name)) return code;
  }
  return std::nullopt;
}

bool FaultThrottle::Admit(fault_t* fault) {
  const auto key = std::make_pair(fault->channel, fault->code);
  auto it = entries_.find(key);
  if (it == entries_.end()) {
    entries_.emplace(key, Entry{fault->utime, 0});
    return true;
  }
  Entry& e = it->second;
  if (fault->utime - e.last_sent_utime < interval_us_) {
    ++e.suppressed;
    ++suppressed_total_;
    return false;
  }
  if (e.suppressed > 0) {
    fault->reason += " (and " + std::to_string(e.suppressed) + " more like it since the last report)";
  }
  e.last_sent_utime = fault->utime;
  e.suppressed = 0;
  return true;
}

fault_t MakeFault(const std::string& node, const std::string& channel, FaultCode code, std::int8_t severity,
                  std::string reason, std::int64_t utime) {
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
