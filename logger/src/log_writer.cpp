#include "edsp/logger/log_writer.h"

#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include <fmt/format.h>

namespace edsp {

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
  LogResume resume;
  std::string error;
  auto file = LogFileAppender::Open(path, &resume, &error);
  if (file == nullptr) throw std::runtime_error(error);
  if (file_ != nullptr) FlushFile();
  file_ = std::move(file);
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.path = path;
  if (part_ == 0) {
    stats_.resumed_events = resume.events;
    stats_.torn_bytes_cut = resume.torn_bytes;
  }
}

bool LogWriter::Enqueue(const std::string& channel, const std::uint8_t* data, std::uint32_t size, std::int64_t utime) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (queued_bytes_ + waiting_bytes_ + size > options_.max_queue_bytes) {
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
  // A new part only once the current one holds everything it was given.
  if (options_.rotate_bytes > 0 && file_->file_bytes() >= options_.rotate_bytes && file_->pending_events() == 0) {
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
  file_->Append(e.channel, e.data.data(), static_cast<std::uint32_t>(e.data.size()), e.utime);
  std::int64_t dropped = 0;
  if (file_->pending_bytes() > options_.max_queue_bytes) {
    dropped = file_->DropPendingAbove(options_.max_queue_bytes);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.dropped += dropped;
  stats_.waiting_events = file_->pending_events();
  waiting_bytes_ = file_->pending_bytes();
}

void LogWriter::FlushFile() {
  std::string error;
  const std::int64_t before = file_->pending_events();
  const bool ok = file_->Flush(&error);
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.written += before - file_->pending_events();
  stats_.waiting_events = file_->pending_events();
  waiting_bytes_ = file_->pending_bytes();
  if (ok) {
    if (stats_.disk_failing) ++stats_.recoveries;
    stats_.disk_failing = false;
  } else {
    ++stats_.write_errors;
    stats_.disk_failing = true;
    stats_.last_error = error;
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
    // A failing disk is retried at the flush interval, not at every event.
    if (Clock::now() >= next_flush || stopping) {
      FlushFile();
      next_flush = Clock::now() + std::chrono::milliseconds(options_.flush_ms);
    }
    if (stopping) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!queue_.empty()) continue;
      stats_.dropped += file_->pending_events();  // the disk refused them to the end
      return;
    }
  }
}

}  // namespace edsp
