#pragma once
// How late this run's machine let a periodic node run, measured from its
// log: the thresholds of the multi-process tests add it, so that they hold
// on a cold, busy or sanitized machine and still fail when a hold or a
// report never comes.

#include <algorithm>
#include <climits>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "edsp/channels.h"
#include "edsp/fault_t.hpp"
#include "edsp/message_types.h"
#include "edsp/logger/log_reader.h"
#include "edsp/node/fault.h"

namespace edsp::test_support {

// Whether `data` decodes whole as the type `channel` carries (channels.h):
// a foreign or truncated packet someone else sent on it is no cycle of its
// publisher's, and its seq must not break the publisher's pairs.
inline bool DecodesAsItsChannelsType(const std::string& channel, const std::vector<std::uint8_t>& data) {
  const channel::Channel* row = channel::Find(channel);
  if (row == nullptr) return true;  // not edsp's: taken as it parses
  bool decodes = false;
  ForEachMessageType([&](auto tag) {
    using Msg = typename decltype(tag)::type;
    if (Msg::getTypeName() != row->type) return;
    Msg message;
    decodes = message.decode(data.data(), 0, static_cast<int>(data.size())) == static_cast<int>(data.size());
  });
  return decodes;
}

// The largest time beyond `period_us` between two messages of `channel`
// with consecutive seq (a late cycle, not a lost packet), on the
// publisher's own clock (the message's utime), leaving out pairs that
// overlap [skip_from, skip_to] (a fault the test caused there) and, when
// given, pairs outside [within_from, within_to] (the time around a fault:
// a stall at start-up says nothing about the machine when the fault came).
// Only messages that decode whole as the channel's type count (a flood of
// foreign packets on it would otherwise hide a stall between them).
inline std::int64_t LargestLateCycleUs(const std::string& log_path, const std::string& channel, std::int64_t period_us,
                                       std::int64_t skip_from = 0, std::int64_t skip_to = -1,
                                       std::int64_t within_from = 0, std::int64_t within_to = INT64_MAX) {
  LogReader reader(log_path);
  LogEvent event;
  EdspHeader previous, header;
  bool have_previous = false;
  std::int64_t late = 0;
  while (reader.Next(&event)) {
    if (event.channel != channel || !ParseEdspHeader(event.data, &header)) continue;
    if (!DecodesAsItsChannelsType(channel, event.data)) continue;
    const bool overlaps = header.utime >= skip_from && previous.utime <= skip_to;
    const bool within = previous.utime >= within_from && header.utime <= within_to;
    if (have_previous && header.seq == previous.seq + 1 && !overlaps && within) {
      late = std::max(late, header.utime - previous.utime - period_us);
    }
    previous = header;
    have_previous = true;
  }
  return late;
}

// The longest the rig emulator's process stood within [within_from,
// within_to], from when the logger received its truth. Woken late, the
// emulator catches its physics up (up to 50 cycles, each stamped at its own
// instant), so its stamps show no gap; but its drives' image went unwritten
// meanwhile, a drive outage to the bridge. A silence of its truth counts
// only while the logger kept receiving the bridge's readings all through
// it: a stalled logger, which receives nothing and then a burst, is no
// stalled rig.
inline std::int64_t LargestRigStandUs(const std::string& log_path, std::int64_t within_from,
                                      std::int64_t within_to = INT64_MAX) {
  constexpr std::int64_t kPeriodUs = 1000;
  LogReader reader(log_path);
  LogEvent event;
  std::int64_t last_truth = -1, last_reading = -1, widest_reading_gap = 0, longest = 0;
  while (reader.Next(&event)) {
    const std::int64_t t = event.timestamp_utime;
    if (event.channel == "EDSP_LEG_STATE") {
      if (last_truth >= 0) widest_reading_gap = std::max(widest_reading_gap, t - std::max(last_reading, last_truth));
      last_reading = t;
      continue;
    }
    if (event.channel != "EDSP_RIG_TRUTH") continue;
    if (last_truth >= 0 && last_truth >= within_from && t <= within_to) {
      const std::int64_t silence = t - last_truth;
      const bool logger_listened =
          last_reading > last_truth && widest_reading_gap < silence / 4 && t - last_reading < silence / 4;
      if (logger_listened) longest = std::max(longest, silence - kPeriodUs);
    }
    last_truth = t;
    widest_reading_gap = 0;
  }
  return longest;
}

// The rig emulator's drives are lost to the bridge after this long silent
// (VirtualRigBackend's timeout), whatever the bridge's stale limit.
inline constexpr std::int64_t kDrivesTimeoutUs = 50000;

// How late the machine let the bridge's inputs come within [within_from,
// within_to]: the largest late cycle of the loops feeding it and of its own
// (commands), and how long the rig emulator's drives were silent (its
// truth's stamps: time its physics stood past the catch-up; its stands,
// LargestRigStandUs: time its drives' image went unwritten).
struct LatenessAroundTheBridge {
  std::int64_t commands_late_us = 0;
  std::int64_t drives_silent_us = 0;

  // A latch is the machine's when either came to half the limit the bridge
  // latches at (its stale limit; the drives' timeout) or more: what a log
  // shows of a stall is a lower bound of it.
  bool ExplainsALatch(std::int64_t stale_us) const {
    return commands_late_us > stale_us / 2 || drives_silent_us > kDrivesTimeoutUs / 2;
  }
  std::string Describe() const {
    return "commands late " + std::to_string(commands_late_us / 1000) + " ms at most, the rig's drives silent " +
           std::to_string(drives_silent_us / 1000) + " ms at most";
  }
};

// When the bridge first latched in a log (its first `latched` fault), if it did.
inline std::optional<std::int64_t> FirstBridgeLatchUtime(const std::string& log_path) {
  LogReader reader(log_path);
  LogEvent event;
  while (reader.Next(&event)) {
    if (event.channel != "EDSP_FAULT") continue;
    fault_t f;
    if (f.decode(event.data.data(), 0, static_cast<int>(event.data.size())) < 0) continue;
    if (f.node == "actuator_bridge" && f.code == static_cast<std::int32_t>(FaultCode::kLatched)) return f.utime;
  }
  return std::nullopt;
}

inline LatenessAroundTheBridge LatenessAroundTheBridgeWithin(const std::string& log_path, std::int64_t within_from,
                                                             std::int64_t within_to = INT64_MAX) {
  LatenessAroundTheBridge late;
  for (const char* channel : {"EDSP_SETPOINT", "EDSP_LEG_COMMAND", "EDSP_LEG_STATE"}) {
    late.commands_late_us =
        std::max(late.commands_late_us, LargestLateCycleUs(log_path, channel, 1000, 0, -1, within_from, within_to));
  }
  late.drives_silent_us = std::max(LargestLateCycleUs(log_path, "EDSP_RIG_TRUTH", 1000, 0, -1, within_from, within_to),
                                   LargestRigStandUs(log_path, within_from, within_to));
  return late;
}

}  // namespace edsp::test_support
