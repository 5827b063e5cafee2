// edsp-logger: records chosen channels to standard LCM log files that
// lcm-logplayer replays (LoggerNode, edsp/logger/logger_node.h). Rotates by
// size, flushes on a timer (a crash or a full disk loses at most one flush
// interval), counts messages lost by their seq numbers per channel and
// reports them on EDSP_STATUS. Channels this host reads on shared memory are
// taken there, whole. A full disk is an EDSP_FAULT (error) while events wait
// in memory (--max-queue-mb, then dropped and counted), and another (info)
// when writing resumes; the file always ends on a whole event. An existing
// file is appended to (a restarted logger keeps what its predecessor wrote).
//   edsp-logger [--channels 'EDSP_.*'] [--output DIR|FILE] [--rotate-mb 0]
//               [--flush-ms 200] [--max-queue-mb 256] [--group FILE] [--lcm-url URL]
#include "edsp/logger/logger_node.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"

namespace edsp {
namespace {

int Run(int argc, char** argv) {
  NodeApp app{"edsp-logger: record LCM channels to log files"};
  LoggerOptions options;
  double rotate_mb = 0.0, max_queue_mb = 256.0;
  app.add_option("--channels", options.channels, "POSIX extended regex of channels to record");
  app.add_option("--output", options.writer.output, "directory (timestamped names) or file");
  app.add_option("--rotate-mb", rotate_mb, "start a new part after this many MB (0: never)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--flush-ms", options.writer.flush_ms, "flush to disk at least this often")
      ->check(CLI::Range(1, 60000));
  app.add_option("--max-queue-mb", max_queue_mb, "events held in memory while the disk lags or is full")
      ->check(CLI::Range(0.1, 65536.0));
  CLI11_PARSE(app, argc, argv);
  options.writer.rotate_bytes = static_cast<std::int64_t>(rotate_mb * 1e6);
  options.writer.max_queue_bytes = static_cast<std::int64_t>(max_queue_mb * 1e6);

  InstallStopSignals();
  Bus bus(TransportFor(app.node));
  LoggerNode logger(bus, options);
  logger.Run(StopRequested);
  return 0;  // the writer drains, flushes and closes
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-logger", edsp::Run, argc, argv); }
