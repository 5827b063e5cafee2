#include "edsp/logger/log_reader.h"

#include <sys/stat.h>

#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

namespace edsp {

namespace {

std::int64_t ReadBigEndian64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int k = 0; k < 8; ++k) v = (v << 8) | p[k];
  return static_cast<std::int64_t>(v);
}

}  // namespace

bool ParseEdspHeader(const std::vector<std::uint8_t>& data, EdspHeader* header) {
  if (data.size() < 24) return false;
  header->fingerprint = ReadBigEndian64(data.data());
  header->utime = ReadBigEndian64(data.data() + 8);
  header->seq = ReadBigEndian64(data.data() + 16);
  return true;
}

struct LogReader::Impl {
  explicit Impl(const std::string& path) : file(path, "r") {}
  lcm::LogFile file;
};

LogReader::LogReader(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(path + ": no such log file");
  file_size_ = static_cast<std::int64_t>(st.st_size);
  impl_ = std::make_unique<Impl>(path);
  if (!impl_->file.good()) throw std::runtime_error(path + ": cannot open as an LCM log");
}

LogReader::~LogReader() = default;

bool LogReader::Next(LogEvent* event) {
  // LCM says "no more" both at the end and at damage: bytes left where no
  // whole event could be read mean damage, starting where that read began.
  const long before = std::ftell(impl_->file.getFilePtr());
  const lcm::LogEvent* e = impl_->file.readNextEvent();
  if (e == nullptr) {
    if (before >= 0 && before < file_size_) {
      damaged_ = true;
      damage_offset_ = before;
    }
    return false;
  }
  event->event_number = e->eventnum;
  event->timestamp_utime = e->timestamp;
  event->channel = e->channel;
  const auto* bytes = static_cast<const std::uint8_t*>(e->data);
  event->data.assign(bytes, bytes + e->datalen);
  return true;
}

bool IsSharedEdspChannel(const std::string& channel) {
  return channel == "EDSP_STATUS" || channel == "EDSP_FAULT";
}

}  // namespace edsp
