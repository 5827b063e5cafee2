// edsp-logger: records chosen channels to standard LCM log files that
// lcm-logplayer replays. Rotates by size, flushes on a timer (so a crash or a
// full disk loses at most one flush interval), counts messages lost by their
// seq numbers per channel and reports them on EDSP_STATUS.
// Disk writes run on their own thread (edsp/logger/log_writer.h), so a
// stalling disk never makes the logger miss packets.
//   edsp-logger [--channels 'EDSP_.*'] [--output DIR|FILE] [--rotate-mb 0]
//               [--flush-ms 200] [--group FILE] [--lcm-url URL]
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

namespace edsp {
namespace {

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
  CLI11_PARSE(app, argc, argv);

  InstallStopSignals();
  LogWriterOptions writer_options;
  writer_options.output = output;
  writer_options.rotate_bytes = static_cast<std::int64_t>(rotate_mb * 1e6);
  writer_options.flush_ms = flush_ms;
  LogWriter writer(writer_options);
  std::fprintf(stderr, "edsp-logger: recording to %s\n", writer.stats().path.c_str());
  Bus bus(TransportFor(node));
  auto status_out = bus.Advertise<node_status_t>("EDSP_STATUS");
  auto faults = bus.Advertise<fault_t>("EDSP_FAULT");
  NodeStatus status("logger");
  status.SetState(node_status_t::STATE_RUNNING);
  std::map<std::string, std::int64_t> last_seq;  // edsp channels with one publisher
  std::int64_t gaps = 0;
  bool disk_ok_reported = false;
  bus.lcm().SubscribePattern(channels, [&](const std::string& channel, const std::uint8_t* data,
                                           std::uint32_t size) {
    status.CountIn();
    if (writer.Enqueue(channel, data, size, UtimeNow())) status.CountOut();
    std::vector<std::uint8_t> head(data, data + std::min<std::uint32_t>(size, 24));
    EdspHeader header;
    if (!IsSharedEdspChannel(channel) && ParseEdspHeader(head, &header)) {
      auto [it, fresh] = last_seq.emplace(channel, header.seq);
      if (!fresh) {
        if (header.seq > it->second + 1) gaps += header.seq - it->second - 1;
        it->second = header.seq;
      }
    }
  });
  while (!StopRequested()) {
    bus.Handle(std::chrono::milliseconds(20));
    const std::int64_t now = UtimeNow();
    if (status.Due(now)) {
      const LogWriterStats w = writer.stats();
      status.SetDrops(gaps + w.dropped);
      if ((w.write_errors > 0 || w.dropped > 0) && !disk_ok_reported) {
        disk_ok_reported = true;  // once; what is on disk stays readable
        faults.Publish(MakeFault("logger", "", FaultCode::kBackend, fault_t::SEVERITY_ERROR,
                                 w.write_errors > 0 ? w.last_error
                                                    : fmt::format("{} events dropped: the disk cannot keep up", w.dropped),
                                 now));
        status.SetState(node_status_t::STATE_FAULT);
      }
      status_out.Publish(status.Report(now, 0));
    }
  }
  return 0;  // the writer drains, flushes and closes
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-logger", edsp::Run, argc, argv); }
