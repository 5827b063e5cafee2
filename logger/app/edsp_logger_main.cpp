// edsp-logger: records chosen channels to standard LCM log files that
// lcm-logplayer replays. Rotates by size, flushes on a timer (so a crash or a
// full disk loses at most one flush interval), counts messages lost by their
// seq numbers per channel and reports them on EDSP_STATUS.
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
#include "edsp/node/fault.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

namespace edsp {
namespace {

bool IsDirectory(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// <dir>/edsp-YYYYmmdd-HHMMSS.NN.lcmlog, or the file given, with .NN before
// the extension from the second part on.
std::string PartPath(const std::string& output, const std::string& stamp, int part) {
  if (IsDirectory(output)) return fmt::format("{}/edsp-{}.{:02d}.lcmlog", output, stamp, part);
  if (part == 0) return output;
  const std::size_t dot = output.rfind('.');
  return dot == std::string::npos ? fmt::format("{}.{:02d}", output, part)
                                  : fmt::format("{}.{:02d}{}", output.substr(0, dot), part, output.substr(dot));
}

class Recorder {
 public:
  Recorder(std::string output, std::int64_t rotate_bytes) : output_(std::move(output)), rotate_bytes_(rotate_bytes) {
    char stamp[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
    stamp_ = stamp;
    Open();
  }

  // False if the disk refused the event (reported, and the file so far kept).
  bool Write(const std::string& channel, const std::uint8_t* data, std::uint32_t size, std::int64_t utime) {
    if (rotate_bytes_ > 0 && bytes_ >= rotate_bytes_) {
      ++part_;
      Open();
    }
    lcm::LogEvent event{};
    event.eventnum = eventnum_++;
    event.timestamp = utime;
    event.channel = channel;
    event.datalen = static_cast<std::int32_t>(size);
    event.data = const_cast<std::uint8_t*>(data);
    if (log_->writeEvent(&event) != 0) return false;
    bytes_ += size + static_cast<std::int64_t>(channel.size()) + 28;
    return true;
  }

  bool Flush() { return std::fflush(log_->getFilePtr()) == 0; }
  const std::string& path() const { return path_; }

 private:
  void Open() {
    if (log_ != nullptr) Flush();
    path_ = PartPath(output_, stamp_, part_);
    log_ = std::make_unique<lcm::LogFile>(path_, "w");
    if (!log_->good()) throw std::runtime_error(path_ + ": cannot create log file: " + std::strerror(errno));
    bytes_ = 0;
    std::fprintf(stderr, "edsp-logger: recording to %s\n", path_.c_str());
  }

  std::string output_, stamp_, path_;
  std::int64_t rotate_bytes_;
  int part_ = 0;
  std::int64_t bytes_ = 0, eventnum_ = 0;
  std::unique_ptr<lcm::LogFile> log_;
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
  CLI11_PARSE(app, argc, argv);

  InstallStopSignals();
  Recorder recorder(output, static_cast<std::int64_t>(rotate_mb * 1e6));
  Bus bus(TransportFor(node));
  auto status_out = bus.Advertise<node_status_t>("EDSP_STATUS");
  auto faults = bus.Advertise<fault_t>("EDSP_FAULT");
  NodeStatus status("logger");
  status.SetState(node_status_t::STATE_RUNNING);
  std::map<std::string, std::int64_t> last_seq;  // edsp channels with one publisher
  std::int64_t gaps = 0;
  bool disk_ok = true;
  bus.lcm().SubscribePattern(channels, [&](const std::string& channel, const std::uint8_t* data,
                                           std::uint32_t size) {
    status.CountIn();
    const std::int64_t now = UtimeNow();
    if (recorder.Write(channel, data, size, now)) {
      status.CountOut();
    } else if (disk_ok) {
      disk_ok = false;  // report once; what is on disk stays readable
      faults.Publish(MakeFault("logger", channel, FaultCode::kBackend, fault_t::SEVERITY_ERROR,
                               recorder.path() + ": write failed (disk full?): " + std::strerror(errno), now));
      status.SetState(node_status_t::STATE_FAULT);
    }
    std::vector<std::uint8_t> head(data, data + std::min<std::uint32_t>(size, 24));
    EdspHeader header;
    if (channel != "EDSP_STATUS" && channel != "EDSP_FAULT" && ParseEdspHeader(head, &header)) {
      auto [it, fresh] = last_seq.emplace(channel, header.seq);
      if (!fresh) {
        if (header.seq > it->second + 1) gaps += header.seq - it->second - 1;
        it->second = header.seq;
      }
    }
  });
  std::int64_t next_flush = 0;
  while (!StopRequested()) {
    bus.Handle(std::chrono::milliseconds(20));
    const std::int64_t now = UtimeNow();
    if (now >= next_flush) {
      recorder.Flush();
      next_flush = now + std::int64_t{flush_ms} * 1000;
    }
    if (status.Due(now)) {
      status.SetDrops(gaps);
      status_out.Publish(status.Report(now, 0));
    }
  }
  recorder.Flush();
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) {
  try {
    return edsp::Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-logger: error: %s\n", e.what());
    return 1;
  }
}
