// edsp-logger: records chosen channels to standard LCM log files that
// lcm-logplayer replays. Rotates by size, flushes on a timer (so a crash or a
// full disk loses at most one flush interval), counts messages lost by their
// seq numbers per channel and reports them on EDSP_STATUS.
// Disk writes run on their own thread (edsp/logger/log_writer.h), so a
// stalling disk never makes the logger miss packets. A full disk is an
// EDSP_FAULT (error) while events wait in memory (--max-queue-mb, then
// dropped and counted), and another (info) when writing resumes; the file
// always ends on a whole event. An existing file is appended to (a restarted
// logger keeps what its predecessor wrote, cutting a torn last event).
//   edsp-logger [--channels 'EDSP_.*'] [--output DIR|FILE] [--rotate-mb 0]
//               [--flush-ms 200] [--max-queue-mb 256] [--group FILE] [--lcm-url URL]
#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <map>

#include <fmt/format.h>
#include <lcm/lcm-cpp.hpp>

#include "edsp/logger/log_reader.h"
#include "edsp/logger/log_writer.h"
#include "edsp/node/fault.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"
#include "edsp/transport/seq_gap.h"

namespace edsp {
namespace {

// Says where this logger records, and what it found there when resuming.
template <typename FaultOut>
void ReportOpened(const LogWriterStats& w, FaultOut& faults) {
  std::fprintf(stderr, "edsp-logger: recording to %s\n", w.path.c_str());
  if (w.resumed_events == 0 && w.torn_bytes_cut == 0) return;
  const std::string reason =
      fmt::format("{}: resumed after {} events already recorded{}", w.path, w.resumed_events,
                  w.torn_bytes_cut > 0 ? fmt::format("; cut a torn last event of {} bytes", w.torn_bytes_cut)
                                       : std::string());
  std::fprintf(stderr, "edsp-logger: %s\n", reason.c_str());
  faults.Publish(MakeFault("logger", "", FaultCode::kStorage, fault_t::SEVERITY_INFO, reason, UtimeNow()));
}

// The disk's episodes as faults: one error when writing starts failing, one
// info when it works again, with what was lost in between.
class DiskHealth {
 public:
  bool Update(const LogWriterStats& w, std::int64_t now, fault_t* fault) {
    if (w.disk_failing && !failing_) {
      failing_ = true;
      dropped_at_failure_ = w.dropped;
      *fault = MakeFault("logger", "", FaultCode::kStorage, fault_t::SEVERITY_ERROR,
                         fmt::format("{}; the file ends on a whole event and stays readable", w.last_error), now);
      return true;
    }
    if (!w.disk_failing && failing_) {
      failing_ = false;
      *fault = MakeFault("logger", "", FaultCode::kStorage, fault_t::SEVERITY_INFO,
                         fmt::format("{}: writing again; {} events dropped while the disk refused them",
                                     w.path, w.dropped - dropped_at_failure_),
                         now);
      return true;
    }
    if (w.dropped > reported_dropped_ && !failing_ && !lag_reported_) {
      lag_reported_ = true;  // once: a disk that cannot keep up
      *fault = MakeFault("logger", "", FaultCode::kStorage, fault_t::SEVERITY_ERROR,
                         fmt::format("{} events dropped: the disk cannot keep up", w.dropped), now);
      reported_dropped_ = w.dropped;
      return true;
    }
    return false;
  }
  bool failing() const { return failing_; }

 private:
  bool failing_ = false;
  bool lag_reported_ = false;
  std::int64_t dropped_at_failure_ = 0;
  std::int64_t reported_dropped_ = 0;
};

int Run(int argc, char** argv) {
  CLI::App app{"edsp-logger: record LCM channels to log files"};
  NodeOptions node;
  AddNodeOptions(&app, &node);
  std::string channels = "EDSP_.*", output = ".";
  double rotate_mb = 0.0;
  int flush_ms = 200;
  app.add_option("--channels", channels, "POSIX regex of channels to record");
  app.add_option("--output", output, "directory (timestamped names) or file");
  app.add_option("--rotate-mb", rotate_mb, "start a new part after this many MB (0: never)")->check(CLI::Range(0.0, 1e6));
  app.add_option("--flush-ms", flush_ms, "flush to disk at least this often")->check(CLI::Range(1, 60000));
  double max_queue_mb = 256.0;
  app.add_option("--max-queue-mb", max_queue_mb, "events held in memory while the disk lags or is full")
      ->check(CLI::Range(0.1, 65536.0));
  CLI11_PARSE(app, argc, argv);

  InstallStopSignals();
  LogWriterOptions writer_options;
  writer_options.output = output;
  writer_options.rotate_bytes = static_cast<std::int64_t>(rotate_mb * 1e6);
  writer_options.flush_ms = flush_ms;
  writer_options.max_queue_bytes = static_cast<std::int64_t>(max_queue_mb * 1e6);
  LogWriter writer(writer_options);
  Bus bus(TransportFor(node));
  auto status_out = bus.Advertise<node_status_t>("EDSP_STATUS");
  auto faults = bus.Advertise<fault_t>("EDSP_FAULT");
  NodeStatus status("logger");
  status.SetState(node_status_t::STATE_RUNNING);
  std::map<std::string, std::int64_t> last_seq;  // edsp channels with one publisher
  std::int64_t gaps = 0;
  DiskHealth disk;
  bus.lcm().SubscribePattern(channels, [&](const std::string& channel, const std::uint8_t* data,
                                           std::uint32_t size) {
    status.CountIn();
    if (writer.Enqueue(channel, data, size, UtimeNow())) status.CountOut();
    std::vector<std::uint8_t> head(data, data + std::min<std::uint32_t>(size, 24));
    EdspHeader header;
    if (!IsSharedEdspChannel(channel) && ParseEdspHeader(head, &header)) {
      auto [it, fresh] = last_seq.emplace(channel, header.seq);
      if (!fresh) {
        gaps += SeqGap(it->second, header.seq);
        it->second = header.seq;
      }
    }
  });
  // After subscribing: the logger records its own report (multicast loops back).
  ReportOpened(writer.stats(), faults);
  while (!StopRequested()) {
    bus.Handle(std::chrono::milliseconds(20));
    const std::int64_t now = UtimeNow();
    // The disk's health every pass (20 ms at most), its status once a second
    // and at once when it changes.
    const LogWriterStats w = writer.stats();
    fault_t fault;
    const bool changed = disk.Update(w, now, &fault);
    if (changed) faults.Publish(fault);
    if (status.Due(now) || changed) {
      status.SetDrops(gaps + w.dropped);
      status.SetState(disk.failing() ? node_status_t::STATE_FAULT : node_status_t::STATE_RUNNING);
      status_out.Publish(status.Report(now, 0));
    }
  }
  return 0;  // the writer drains, flushes and closes
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-logger", edsp::Run, argc, argv); }
