#include "edsp/logger/log_file_appender.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "edsp/logger/lcm_log_format.h"

namespace edsp {
namespace {

using lcm_log::kHeaderBytes;
using Header = lcm_log::EventHeader;

bool ReadAt(int fd, std::uint8_t* buffer, std::size_t bytes, std::int64_t offset) {
  std::size_t done = 0;
  while (done < bytes) {
    const ssize_t n = ::pread(fd, buffer + done, bytes - done, offset + static_cast<std::int64_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// Is there a whole event starting anywhere after `from`? (Then the damage at
// `from` is inside the log, not a torn tail.)
bool WholeEventAfter(int fd, std::int64_t from, std::int64_t size) {
  constexpr std::size_t kChunk = 1 << 20;
  std::vector<std::uint8_t> chunk(kChunk + kHeaderBytes);
  for (std::int64_t base = from + 1; base + static_cast<std::int64_t>(kHeaderBytes) <= size;
       base += static_cast<std::int64_t>(kChunk)) {
    const auto bytes =
        static_cast<std::size_t>(std::min<std::int64_t>(static_cast<std::int64_t>(chunk.size()), size - base));
    if (!ReadAt(fd, chunk.data(), bytes, base)) return false;
    for (std::size_t k = 0; k + kHeaderBytes <= bytes && k < kChunk; ++k) {
      Header h{};
      if (lcm_log::ParseEventHeader(chunk.data() + k, size - base - static_cast<std::int64_t>(k), &h)) return true;
    }
  }
  return false;
}

// The whole events of an open log and where the last one ends. A file
// whose damage is only a torn last event has `tail_torn`; damage with whole
// events after it (a sync word further on) has `damaged_inside`.
struct LogScan {
  std::int64_t events = 0;
  std::int64_t last_event_number = -1;
  std::int64_t whole_bytes = 0;
  bool tail_torn = false;
  bool damaged_inside = false;
};

LogScan ScanOpenLog(int fd, std::int64_t size) {
  LogScan scan;
  std::array<std::uint8_t, kHeaderBytes> header{};
  std::int64_t offset = 0;
  while (offset + static_cast<std::int64_t>(kHeaderBytes) <= size) {
    Header h{};
    if (!ReadAt(fd, header.data(), header.size(), offset) ||
        !lcm_log::ParseEventHeader(header.data(), size - offset, &h)) {
      break;
    }
    ++scan.events;
    scan.last_event_number = h.event_number;
    offset += h.total_bytes();
  }
  scan.whole_bytes = offset;
  if (offset < size) {
    scan.damaged_inside = WholeEventAfter(fd, offset, size);
    scan.tail_torn = !scan.damaged_inside;
  }
  return scan;
}

std::string ErrnoText(int error) { return std::strerror(error); }

// Reserves disk room for `bytes` past `at` without changing the file's size:
// a write into reserved room cannot fail half-way for want of space, so a
// reader never meets a torn event, not even for the instant before it would
// be cut back. 0, or the errno (EOPNOTSUPP where the filesystem cannot).
int ReserveRoom(int fd, std::int64_t at, std::size_t bytes) {
  if (bytes == 0) return 0;
  int result;
  do {
    result = ::fallocate(fd, FALLOC_FL_KEEP_SIZE, at, static_cast<off_t>(bytes));
  } while (result != 0 && errno == EINTR);
  return result == 0 ? 0 : errno;
}

// The free bytes the filesystem holding `fd` will give this process.
std::int64_t FreeBytes(int fd) {
  struct statvfs s {};
  if (::fstatvfs(fd, &s) != 0) return 0;
  return static_cast<std::int64_t>(s.f_bavail) * static_cast<std::int64_t>(s.f_frsize);
}

}  // namespace

std::unique_ptr<LogFileAppender> LogFileAppender::Open(const std::string& path, LogResume* resume, std::string* error) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    *error = fmt::format("{}: cannot open the log file: {}", path, ErrnoText(errno));
    return nullptr;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    *error = fmt::format("{}: cannot stat the log file: {}", path, ErrnoText(errno));
    ::close(fd);
    return nullptr;
  }
  const LogScan scan = ScanOpenLog(fd, static_cast<std::int64_t>(st.st_size));
  if (scan.damaged_inside) {
    *error =
        fmt::format("{}: damaged at byte {} with whole events after it; not appending to it", path, scan.whole_bytes);
    ::close(fd);
    return nullptr;
  }
  if (scan.tail_torn && ::ftruncate(fd, scan.whole_bytes) != 0) {
    *error = fmt::format("{}: cannot cut the torn last event at byte {}: {}", path, scan.whole_bytes, ErrnoText(errno));
    ::close(fd);
    return nullptr;
  }
  if (::lseek(fd, scan.whole_bytes, SEEK_SET) < 0) {
    *error = fmt::format("{}: cannot seek: {}", path, ErrnoText(errno));
    ::close(fd);
    return nullptr;
  }
  if (resume != nullptr) {
    resume->events = scan.events;
    resume->torn_bytes = static_cast<std::int64_t>(st.st_size) - scan.whole_bytes;
  }
  return std::unique_ptr<LogFileAppender>(new LogFileAppender(path, fd, scan.whole_bytes, scan.last_event_number + 1));
}

LogFileAppender::LogFileAppender(std::string path, int fd, std::int64_t committed, std::int64_t next_event)
    : path_(std::move(path)), fd_(fd), committed_(committed), next_event_(next_event) {}

LogFileAppender::~LogFileAppender() {
  if (fd_ >= 0) ::close(fd_);
}

void LogFileAppender::Append(const std::string& channel, const std::uint8_t* data, std::uint32_t size,
                             std::int64_t utime) {
  // No reserve() here: an exact reserve per event would defeat the vector's
  // geometric growth and copy the whole pending buffer at every append
  // (quadratic: it stalled the logger under a flood with ASan).
  lcm_log::AppendEventHeader(&pending_, next_event_++, utime, channel.size(), size);
  pending_.insert(pending_.end(), channel.begin(), channel.end());
  pending_.insert(pending_.end(), data, data + size);
  boundaries_.push_back(pending_.size());
}

void LogFileAppender::KeepPendingFrom(std::size_t written_bytes) {
  // The events wholly written leave the buffer; the rest is renumbered
  // relative to what remains.
  const auto first_left = std::upper_bound(boundaries_.begin(), boundaries_.end(), written_bytes);
  const std::size_t whole = first_left == boundaries_.begin() ? 0 : *(first_left - 1);
  committed_ += static_cast<std::int64_t>(whole);
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(whole));
  boundaries_.erase(boundaries_.begin(), first_left);
  for (std::size_t& end : boundaries_) end -= whole;
}

std::size_t LogFileAppender::WholeEventsWithin(std::int64_t bytes) const {
  const auto past = std::upper_bound(boundaries_.begin(), boundaries_.end(),
                                     static_cast<std::size_t>(std::max<std::int64_t>(bytes, 0)));
  return past == boundaries_.begin() ? 0 : *(past - 1);
}

std::size_t LogFileAppender::BytesWithRoom(int* failure) const {
  const int reserve = ReserveRoom(fd_, committed_, pending_.size());
  if (reserve == 0) return pending_.size();
  if (reserve != ENOSPC) {
    // A filesystem without fallocate is written as it comes (a short write
    // is cut back below); any other refusal is the failure itself.
    if (reserve == EOPNOTSUPP || reserve == ENOSYS || reserve == EINVAL) return pending_.size();
    *failure = reserve;
    return 0;
  }
  // Not room for all: the whole events that fit in what is free (less a
  // page the filesystem may need for itself), if even that is granted.
  *failure = ENOSPC;
  const std::size_t fits = WholeEventsWithin(FreeBytes(fd_) - 4096);
  return fits > 0 && ReserveRoom(fd_, committed_, fits) == 0 ? fits : 0;
}

bool LogFileAppender::Flush(std::string* error) {
  int failure = 0;
  const std::size_t with_room = BytesWithRoom(&failure);
  std::size_t written = 0;
  while (written < with_room) {
    const ssize_t n = ::write(fd_, pending_.data() + written, with_room - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      failure = n < 0 ? errno : ENOSPC;  // write() returning 0 for a regular file: no room
      break;
    }
    written += static_cast<std::size_t>(n);
  }
  const bool torn = written != WholeEventsWithin(static_cast<std::int64_t>(written));
  KeepPendingFrom(written);
  if (failure == 0) return true;
  // A write that failed part-way (no room reserved: a filesystem without
  // fallocate, a file-size limit) leaves a partial event: cut the file back
  // to its last whole event, so readers never meet a torn event in the
  // middle of the log.
  if (torn && (::ftruncate(fd_, committed_) != 0 || ::lseek(fd_, committed_, SEEK_SET) < 0)) {
    *error = fmt::format("{}: write failed ({}) and the torn event could not be cut: {}", path_, ErrnoText(failure),
                         ErrnoText(errno));
    return false;
  }
  *error =
      fmt::format("{}: write failed: {} ({} events waiting in memory)", path_, ErrnoText(failure), boundaries_.size());
  return false;
}

std::int64_t LogFileAppender::DropPendingAbove(std::int64_t bytes) {
  std::int64_t dropped = 0;
  while (!boundaries_.empty() && static_cast<std::int64_t>(pending_.size()) > bytes) {
    boundaries_.pop_back();
    pending_.resize(boundaries_.empty() ? 0 : boundaries_.back());
    ++dropped;
  }
  return dropped;
}

}  // namespace edsp
