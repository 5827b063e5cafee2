#pragma once
// What every node reports on EDSP_FAULT: the codes, and building the message.

#include <cstdint>
#include <string>

#include "edsp/fault_t.hpp"

namespace edsp {

// fault_t.code values shared by all nodes.
enum class FaultCode : std::int32_t {
  kNonFinite = 1,         // NaN or infinity in an input
  kOutsideWorkspace = 2,  // pose beyond a workspace limit
  kForeignSession = 3,    // command from another launch session
  kStale = 4,             // input older than the stale limit, or none arriving
  kUndecodable = 5,       // truncated or foreign packet
  kJump = 6,              // command too far from the last valid one
  kOutOfStroke = 7,       // leg length beyond its stroke
  kForwardKinematics = 8, // the pose could not be computed from the encoders
  kBackend = 9,           // the drive backend failed
};

const char* FaultCodeName(FaultCode code);

fault_t MakeFault(const std::string& node, const std::string& channel, FaultCode code,
                  std::int8_t severity, std::string reason, std::int64_t utime);

}  // namespace edsp
