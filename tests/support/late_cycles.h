#pragma once
// How late this run's machine let a periodic node run, measured from its
// log: the thresholds of the multi-process tests add it, so that they hold
// on a cold, busy or sanitized machine and still fail when a hold or a
// report never comes.

#include <algorithm>
#include <climits>
#include <cstdint>
#include <string>

#include "edsp/logger/log_reader.h"

namespace edsp::test_support {

// The largest time beyond `period_us` between two messages of `channel`
// with consecutive seq (a late cycle, not a lost packet), on the
// publisher's own clock (the message's utime), leaving out pairs that
// overlap [skip_from, skip_to] (a fault the test caused there) and, when
// given, pairs outside [within_from, within_to] (the time around a fault:
// a stall at start-up says nothing about the machine when the fault came).
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

// The largest late cycle over the loops that feed the bridge, the bridge's
// own, and the rig emulator's drives (its truth reports every physics
// cycle, caught-up ones too, so a gap there is time its drives stood),
// within [within_from, within_to]: what explains a latch of the bridge.
inline std::int64_t LargestLateCycleAroundTheBridgeUs(const std::string& log_path, std::int64_t within_from,
                                                      std::int64_t within_to = INT64_MAX) {
  std::int64_t late = 0;
  for (const char* channel : {"EDSP_SETPOINT", "EDSP_LEG_COMMAND", "EDSP_LEG_STATE", "EDSP_RIG_TRUTH"}) {
    late = std::max(late, LargestLateCycleUs(log_path, channel, 1000, 0, -1, within_from, within_to));
  }
  return late;
}

}  // namespace edsp::test_support
