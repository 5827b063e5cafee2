#pragma once
// edsp-cueing send: a vehicle model's stand-in, for trying a rig and for
// the tests. Sends the packet (docs/cueing.md) at --rate-hz in real time:
// a rider at rest with "engage" for --lead-s (the platform engages), the
// manoeuvre with "engage", then --tail-s of what --after says: "disengage"
// (the cueing washes out and the platform parks), "silence" (no packets:
// the input is lost), "estop", "freeze" or "engage" (at rest).
// With --to lcm the samples go as vehicle_motion_t on EDSP_VEHICLE instead,
// on the bus of --group or --lcm-url, to --session-id (auto: the session
// of the group on that bus, found from its traffic).
//   edsp-cueing send --manoeuvre FILE [--to 127.0.0.1:7400|lcm] [--rate-hz 250]
//                    [--lead-s 5] [--after disengage] [--tail-s 20] [--sent-log FILE]
//                    [--group FILE | --lcm-url URL] [--session-id N|auto]

#include <string>

namespace edsp {

struct SendOptions {
  std::string manoeuvre_path;
  std::string to = "127.0.0.1:7400";  // or "lcm"
  std::string group_path;             // with --to lcm: the bus
  std::string lcm_url;
  std::string session = "auto";
  double rate_hz = 250.0;
  double lead_s = 5.0;
  std::string after = "disengage";
  double tail_s = 20.0;
  // Each packet's sequence and when it went out (the host's wall clock,
  // µs), as CSV "sequence,sent_utime": what `edsp-cueing delay` traces.
  std::string sent_log_path;
};

int RunSend(const SendOptions& options);

}  // namespace edsp
