#include "edsp/logger/log_writer.h"

#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include <fmt/format.h>
#include <lcm/lcm-cpp.hpp>

namespace edsp {

struct LogWriter::File {
  explicit File(const std::string& path) : log(path, "w") {}
  lcm::LogFile log;
};

std::string LogPartPath(const std::string& output, const std::string& stamp, int part) {
  struct stat st {};
  if (::stat(output.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    return fmt::format("{}/edsp-{}.{:02d}.lcmlog", output, stamp, part);
  }
  if (part == 0) return output;
  const std::size_t slash = output.rfind('/');
  const std::size_t dot = output.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) {
    return fmt::format("{}.{:02d}", output, part);
  }
  return fmt::format("{}.{:02d}{}", output.substr(0, dot), part, output.substr(dot));
}

LogWriter::LogWriter(LogWriterOptions options) : options_(std::move(options)) {
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
  stamp_ = stamp;
  OpenPart();
  thread_ = std::thread([this] { Run(); });
}

LogWriter::~LogWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void LogWriter::OpenPart() {
  const std::string path = LogPartPath(options_.output, stamp_, part_);
  auto file = std::make_unique<File>(path);
  if (!file->log.good()) {
    throw std::runtime_error(path + ": cannot create log file: " + std::strerror(errno));
  }
  if (file_ != nullptr) std::fflush(file_->log.getFilePtr());
  file_ = std::move(file);
  part_bytes_ = 0;
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.path = path;
}

bool LogWriter::Enqueue(const std::string& channel, const std::uint8_t* data, std::uint32_t size,
                        std::int64_t utime) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (queued_bytes_ + size > options_.max_queue_bytes) {
      ++stats_.dropped;
      return false;
    }
    queue_.push_back(Event{channel, std::vector<std::uint8_t>(data, data + size), utime});
    queued_bytes_ += size;
  }
  wake_.notify_one();
  return true;
}

LogWriterStats LogWriter::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

void LogWriter::WriteOne(const Event& e) {
  if (options_.rotate_bytes > 0 && part_bytes_ >= options_.rotate_bytes) {
    ++part_;
    try {
      OpenPart();
    } catch (const std::exception& error) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++stats_.write_errors;
      stats_.last_error = error.what();
      --part_;  // keep writing the old part
    }
  }
  lcm::LogEvent event{};
  event.eventnum = eventnum_++;
  event.timestamp = e.utime;
  event.channel = e.channel;
  event.datalen = static_cast<std::int32_t>(e.data.size());
  event.data = const_cast<std::uint8_t*>(e.data.data());
  const bool ok = file_->log.writeEvent(&event) == 0;
  part_bytes_ += static_cast<std::int64_t>(e.data.size() + e.channel.size()) + 28;
  std::lock_guard<std::mutex> lock(mutex_);
  if (ok) {
    ++stats_.written;
  } else {
    ++stats_.write_errors;
    stats_.last_error = stats_.path + ": write failed (disk full?): " + std::strerror(errno);
  }
}

void LogWriter::Run() {
  using Clock = std::chrono::steady_clock;
  auto next_flush = Clock::now() + std::chrono::milliseconds(options_.flush_ms);
  std::deque<Event> batch;
  for (;;) {
    bool stopping;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait_until(lock, next_flush, [&] { return stopping_ || !queue_.empty(); });
      batch.swap(queue_);
      queued_bytes_ = 0;
      stopping = stopping_;
    }
    for (const Event& e : batch) WriteOne(e);
    batch.clear();
    if (Clock::now() >= next_flush || stopping) {
      std::fflush(file_->log.getFilePtr());
      next_flush = Clock::now() + std::chrono::milliseconds(options_.flush_ms);
    }
    if (stopping) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (queue_.empty()) return;
    }
  }
}

}  // namespace edsp
