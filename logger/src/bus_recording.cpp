#include "edsp/logger/bus_recording.h"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <exception>
#include <map>
#include <stdexcept>

#include "edsp/logger/log_file_appender.h"
#include "edsp/node/runtime.h"

namespace edsp {

namespace {
constexpr auto kHandleSlice = std::chrono::milliseconds(20);  // how soon Stop() is seen
}  // namespace

BusRecording::BusRecording(const TransportConfig& config, const std::string& channel_pattern, std::int64_t max_bytes)
    : bus_(std::make_unique<Bus>(config)), max_bytes_(max_bytes) {
  shm_channels_ = bus_->SubscribeRaw(channel_pattern, [this](const std::string& channel, const std::uint8_t* data,
                                                             std::uint32_t size) { Keep(channel, data, size); });
  thread_ = std::thread([this] { Run(); });
}

BusRecording::~BusRecording() { Stop(); }

void BusRecording::Stop() {
  stopping_ = true;
  std::call_once(stopped_, [this] {
    if (thread_.joinable()) thread_.join();
    std::int64_t overruns = 0;
    for (const std::string& channel : shm_channels_)
      overruns += static_cast<std::int64_t>(bus_->Counters(channel).overruns);
    const std::lock_guard<std::mutex> lock(mutex_);
    stats_.overruns = overruns;
  });
}

void BusRecording::Run() {
  try {
    while (!stopping_) bus_->Handle(kHandleSlice);
    bus_->Handle(std::chrono::microseconds(0));  // what the rings got since the last read
  } catch (const std::exception& e) {
    const std::lock_guard<std::mutex> lock(mutex_);
    stats_.error = e.what();
  }
}

void BusRecording::Keep(const std::string& channel, const std::uint8_t* data, std::uint32_t size) {
  const std::int64_t now = UtimeNow();
  const std::lock_guard<std::mutex> lock(mutex_);
  if (stats_.bytes + static_cast<std::int64_t>(size) > max_bytes_) {
    ++stats_.dropped;
    return;
  }
  events_.push_back(LogEvent{stats_.messages, now, channel, std::vector<std::uint8_t>(data, data + size)});
  ++stats_.messages;
  stats_.bytes += size;
}

BusRecordingStats BusRecording::stats() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

MessageColumns BusRecording::Columns() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  MessageColumns columns;
  std::map<std::string, std::int64_t> counts;  // each table made its length at once
  for (const LogEvent& e : events_) ++counts[e.channel];
  for (const auto& [channel, n] : counts) columns.Expect(channel, n);
  for (const LogEvent& e : events_) columns.Add(e.channel, e.data.data(), e.data.size(), e.timestamp_utime);
  return columns;
}

void BusRecording::Save(const std::string& path) const {
  if (std::remove(path.c_str()) != 0 && errno != ENOENT) {
    throw std::runtime_error(path + ": cannot replace the file");
  }
  LogResume resume;
  std::string error;
  const std::unique_ptr<LogFileAppender> file = LogFileAppender::Open(path, &resume, &error);
  if (!file) throw std::runtime_error(error);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const LogEvent& e : events_) {
      file->Append(e.channel, e.data.data(), static_cast<std::uint32_t>(e.data.size()), e.timestamp_utime);
    }
  }
  if (!file->Flush(&error)) throw std::runtime_error(path + ": " + error);
}

}  // namespace edsp
