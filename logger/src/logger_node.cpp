#include "edsp/logger/logger_node.h"

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/logger/log_reader.h"
#include "edsp/node/fault.h"
#include "edsp/node/node_loop.h"

namespace edsp {

namespace {
constexpr auto kPollInterval = std::chrono::milliseconds(20);
}  // namespace

LoggerNode::LoggerNode(Bus& bus, LoggerOptions options)
    : bus_(bus), writer_(options.writer), reporting_(bus, "logger") {
  shm_channels_ = bus.SubscribeRaw(options.channels, [this](const std::string& channel, const std::uint8_t* data,
                                                            std::uint32_t size) { Record(channel, data, size); });
  // After subscribing: the logger records its own report (multicast loops back).
  ReportOpened();
}

void LoggerNode::Record(const std::string& channel, const std::uint8_t* data, std::uint32_t size) {
  reporting_.status().CountIn();
  if (writer_.Enqueue(channel, data, size, UtimeNow())) reporting_.status().CountOut();
  // EDSP_STATUS/EDSP_FAULT: several publishers' seq numbers interleave
  // there; EDSP_VEHICLE's are the vehicle's numbering.
  if (channel::SeqGapsAreNotLosses(channel) || IsOnSharedMemory(channel)) return;
  EdspHeader header;
  if (ParseEdspHeader(data, size, &header)) lcm_seq_gaps_ += seqs_[channel].Count(0, header.seq);
}

bool LoggerNode::IsOnSharedMemory(const std::string& channel) const {
  return std::binary_search(shm_channels_.begin(), shm_channels_.end(), channel);
}

std::int64_t LoggerNode::lost() const {
  std::int64_t lost = lcm_seq_gaps_;
  for (const std::string& channel : shm_channels_) lost += static_cast<std::int64_t>(bus_.Counters(channel).overruns);
  return lost;
}

void LoggerNode::ReportOpened() {
  const LogWriterStats w = writer_.stats();
  std::fprintf(stderr, "edsp-logger: recording to %s\n", w.path.c_str());
  for (const std::string& channel : shm_channels_) {
    std::fprintf(stderr, "edsp-logger: %s read on shared memory\n", channel.c_str());
  }
  if (w.resumed_events == 0 && w.torn_bytes_cut == 0) return;
  const std::string reason = fmt::format(
      "{}: resumed after {} events already recorded{}", w.path, w.resumed_events,
      w.torn_bytes_cut > 0 ? fmt::format("; cut a torn last event of {} bytes", w.torn_bytes_cut) : std::string());
  std::fprintf(stderr, "edsp-logger: %s\n", reason.c_str());
  reporting_.Fault(MakeFault("logger", "", FaultCode::kStorage, fault_t::SEVERITY_INFO, reason, UtimeNow()));
}

void LoggerNode::ReportUnreadableRings(std::int64_t now) {
  for (const std::string& channel : shm_channels_) {
    const std::string& error = bus_.Counters(channel).last_error;
    std::string& reported = reported_ring_errors_[channel];
    if (error.empty() || error == reported) continue;
    reported = error;
    reporting_.Fault(MakeFault("logger", channel, FaultCode::kTransport, fault_t::SEVERITY_WARNING,
                               fmt::format("{}: cannot read its shared memory ({}); recording its LCM copy, which may "
                                           "be a decimated mirror",
                                           channel, error),
                               now));
  }
}

void LoggerNode::Poll(std::int64_t now) {
  ReportUnreadableRings(now);
  const LogWriterStats w = writer_.stats();
  fault_t fault;
  const bool changed = disk_.Update(w, now, &fault);
  if (changed) reporting_.Fault(fault);
  NodeStatus& status = reporting_.status();
  status.SetDrops(lost() + w.dropped);
  status.SetState(disk_.failing() ? node_status_t::STATE_FAULT : node_status_t::STATE_RUNNING);
  reporting_.StatusTick(now, 0);  // at once when the state changed
}

void LoggerNode::Run(const std::function<bool()>& stop) {
  RunPolled(bus_, kPollInterval, stop, [this](std::int64_t now) { Poll(now); });
  // Its rings are read every few ms, not on each message: what came since
  // the last read is taken before the log closes.
  bus_.Handle(std::chrono::microseconds(0));
}

}  // namespace edsp
