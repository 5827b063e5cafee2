#include "delay_command.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/channels.h"
#include "edsp/cueing/cueing_delay.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/logger/logged_message.h"
#include "edsp/pose_setpoint_t.hpp"

namespace edsp {

namespace {

std::vector<SentSample> ReadSent(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("--sent {}: cannot be read", path));
  std::string line;
  std::getline(in, line);
  if (line != "sequence,sent_utime") {
    throw std::runtime_error(fmt::format("--sent {}: line 1 is \"{}\", not \"sequence,sent_utime\"", path, line));
  }
  std::vector<SentSample> sent;
  for (int number = 2; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    SentSample s;
    char comma = 0;
    if (!(fields >> s.sequence >> comma >> s.sent_utime) || comma != ',') {
      throw std::runtime_error(fmt::format("--sent {}: line {} \"{}\" is not sequence,sent_utime", path, number, line));
    }
    sent.push_back(s);
  }
  return sent;
}

CueingDelays TraceLog(const std::string& log_path, const std::vector<SentSample>& sent) {
  std::vector<CueingSetpointLink> setpoints;
  std::vector<CommandLink> commands;
  std::vector<DriveWrite> writes;
  LogReader reader(log_path);
  LogEvent event;
  while (reader.Next(&event)) {
    if (pose_setpoint_t s; event.channel == channel::kSetpoint && DecodeEvent(event, &s)) {
      if (s.phase == pose_setpoint_t::PHASE_CUEING) setpoints.push_back({s.seq, s.segment, event.timestamp_utime});
    } else if (leg_command_t c; event.channel == channel::kLegCommand && DecodeEvent(event, &c)) {
      commands.push_back({c.seq, c.setpoint_seq});
    } else if (leg_state_t w; event.channel == channel::kLegState && DecodeEvent(event, &w)) {
      writes.push_back({event.timestamp_utime, w.command_seq});
    }
  }
  return TraceCueingDelays(sent, setpoints, commands, writes);
}

}  // namespace

int RunDelay(const DelayOptions& options) {
  const CueingDelays d = TraceLog(options.log_path, ReadSent(options.sent_path));
  const double min_ms = d.Percentile(0.0) * 1e3, p50_ms = d.Percentile(0.5) * 1e3, p99_ms = d.Percentile(0.99) * 1e3,
               max_ms = d.Percentile(1.0) * 1e3;
  if (options.json) {
    const nlohmann::json j = {{"samples_sent", d.sent}, {"samples_traced", d.delays_s.size()},
                              {"delay_min_ms", min_ms}, {"delay_p50_ms", p50_ms},
                              {"delay_p99_ms", p99_ms}, {"delay_max_ms", max_ms}};
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%zu of %zu vehicle samples traced to the drives: delay p50 %.2f ms, p99 %.2f ms, max %.2f ms\n",
                d.delays_s.size(), d.sent, p50_ms, p99_ms, max_ms);
  }
  if (d.delays_s.empty()) {
    std::fprintf(stderr, "edsp-cueing delay: no sample of %s traced through %s (no cueing setpoint carries one)\n",
                 options.sent_path.c_str(), options.log_path.c_str());
    return 1;
  }
  return 0;
}

}  // namespace edsp
