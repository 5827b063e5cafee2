#include "edsp/logger/log_reader.h"

#include <sys/stat.h>

#include <cstdio>
#include <stdexcept>

#include "edsp/logger/lcm_log_format.h"

namespace edsp {

namespace {

std::int64_t ReadBigEndian64(const std::uint8_t* p) { return static_cast<std::int64_t>(lcm_log::GetBigEndian(p, 8)); }

}  // namespace

bool ParseEdspHeader(const std::uint8_t* data, std::size_t size, EdspHeader* header) {
  if (size < 24) return false;
  header->fingerprint = ReadBigEndian64(data);
  header->utime = ReadBigEndian64(data + 8);
  header->seq = ReadBigEndian64(data + 16);
  return true;
}

bool ParseEdspHeader(const std::vector<std::uint8_t>& data, EdspHeader* header) {
  return ParseEdspHeader(data.data(), data.size(), header);
}

struct LogReader::Impl {
  std::vector<char> buffer = std::vector<char>(1 << 20);  // outlives the stream that uses it
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file{nullptr, &std::fclose};
};

LogReader::LogReader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(path + ": no such log file");
  file_size_ = static_cast<std::int64_t>(st.st_size);
  impl_->file.reset(std::fopen(path.c_str(), "rb"));
  if (!impl_->file) throw std::runtime_error(path + ": cannot open as an LCM log");
  std::setvbuf(impl_->file.get(), impl_->buffer.data(), _IOFBF, impl_->buffer.size());
}

LogReader::~LogReader() = default;

bool LogReader::Next(LogEvent* event) {
  // Events are read one after the other from the start: the first bytes
  // that are not a whole event (a torn tail, a foreign byte) are the damage.
  // (LCM's own reader, in Debian's 1.3.1, takes a tail of 1 to 3 bytes, a
  // cut inside a sync word, for a clean end, and reads such a log as whole.)
  if (damaged_ || whole_bytes_ >= file_size_) return false;
  if (!ReadEventAt(event)) {
    damaged_ = true;
    damage_offset_ = whole_bytes_;
    return false;
  }
  return true;
}

bool LogReader::ReadEventAt(LogEvent* event) {
  std::FILE* f = impl_->file.get();
  std::uint8_t raw[lcm_log::kHeaderBytes];
  lcm_log::EventHeader header;
  if (std::fread(raw, 1, sizeof raw, f) != sizeof raw ||
      !lcm_log::ParseEventHeader(raw, file_size_ - whole_bytes_, &header)) {
    return false;
  }
  event->channel.resize(static_cast<std::size_t>(header.channel_bytes));
  event->data.resize(static_cast<std::size_t>(header.data_bytes));
  if (std::fread(&event->channel[0], 1, event->channel.size(), f) != event->channel.size() ||
      std::fread(event->data.data(), 1, event->data.size(), f) != event->data.size()) {
    return false;
  }
  event->event_number = header.event_number;
  event->timestamp_utime = header.timestamp_utime;
  whole_bytes_ += header.total_bytes();
  return true;
}

}  // namespace edsp
