#pragma once
// What every node reports on EDSP_FAULT: the codes, and building the message.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "edsp/fault_t.hpp"

namespace edsp {

// fault_t.code values shared by all nodes.
enum class FaultCode : std::int32_t {
  kNonFinite = 1,          // NaN or infinity in an input
  kOutsideWorkspace = 2,   // pose beyond a workspace limit
  kForeignSession = 3,     // command from another launch session
  kStale = 4,              // input older than the stale limit, or none arriving
  kUndecodable = 5,        // truncated or foreign packet
  kJump = 6,               // command too far from the last valid one
  kOutOfStroke = 7,        // leg length beyond its stroke
  kForwardKinematics = 8,  // the pose could not be computed from the encoders
  kBackend = 9,            // the drive backend failed
  kBadRequest = 10,        // an operator request with a value out of range
  kOperatorAction = 11,    // reserved: logs of older groups confirm operator requests with it (now EDSP_REPLY)
  kStorage = 12,           // the log's disk refused writes (info: it accepts them again)
  kProcess = 13,           // a group member froze, exited or restarted (the launcher)
  kCalibration = 14,       // not a fault: the calibration a node applies (severity info)
  kTransport = 15,         // a channel's shared-memory ring cannot be read (permissions, layout, type)
  kLatched = 16,           // the actuator bridge holds until re-armed (EDSP_ARM): latched, or refusing while so
};

const char* FaultCodeName(FaultCode code);
// The code a user names: its number, or its name as FaultCodeName gives it
// ("drive backend"; "drive_backend" and "drive-backend" too). Empty if none.
std::optional<FaultCode> FaultCodeFromText(const std::string& text);

// Repeated faults (a flood of foreign packets, a stream of stale commands)
// must not flood EDSP_FAULT in turn: at most one per (channel, code) every
// `interval_us`; the next one sent says how many were held back.
class FaultThrottle {
 public:
  explicit FaultThrottle(std::int64_t interval_us = 100000) : interval_us_(interval_us) {}
  // True if `fault` should be published now (its reason then carries the
  // count of the ones suppressed since the last one sent).
  bool Admit(fault_t* fault);
  std::int64_t suppressed_total() const { return suppressed_total_; }

 private:
  struct Entry {
    std::int64_t last_sent_utime;
    std::int64_t suppressed;
  };
  std::int64_t interval_us_;
  std::map<std::pair<std::string, std::int32_t>, Entry> entries_;
  std::int64_t suppressed_total_ = 0;
};

fault_t MakeFault(const std::string& node, const std::string& channel, FaultCode code, std::int8_t severity,
                  std::string reason, std::int64_t utime);

}  // namespace edsp
