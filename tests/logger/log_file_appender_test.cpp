// The logger's file layer: whatever happens (a full disk, a kill mid-write,
// a restart), the file ends on a whole event that LCM's own reader reads,
// and nothing written before is lost. A full disk is RLIMIT_FSIZE (EFBIG at
// a byte limit, like ENOSPC) or a small tmpfs of the test's own.
#include "edsp/logger/log_file_appender.h"

#include <sched.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "edsp/logger/log_reader.h"
#include "edsp/logger/log_writer.h"
#include "scratch_dir.h"

namespace edsp {
namespace {

std::string TempPath(const std::string& name) { return test_support::ScratchRoot() + "/appender_" + name + ".lcmlog"; }

std::vector<std::uint8_t> Payload(int k) {
  std::vector<std::uint8_t> bytes(100 + static_cast<std::size_t>(k % 7) * 13);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<std::uint8_t>(k * 31 + static_cast<int>(i));
  return bytes;
}

void AppendEvents(LogFileAppender* file, int from, int to) {
  for (int k = from; k < to; ++k) {
    const auto bytes = Payload(k);
    file->Append("CH" + std::to_string(k % 3), bytes.data(), static_cast<std::uint32_t>(bytes.size()), 1000 * (k + 1));
  }
}

// Read back by LCM's own reader (an independent implementation of the
// format): damaged if it stops before the end of the file.
std::vector<LogEvent> ReadAll(const std::string& path, bool* damaged) {
  lcm::LogFile file(path, "r");
  std::vector<LogEvent> events;
  long stopped_at = 0;
  while (true) {
    stopped_at = std::ftell(file.getFilePtr());
    const lcm::LogEvent* e = file.readNextEvent();
    if (e == nullptr) break;
    const auto* bytes = static_cast<const std::uint8_t*>(e->data);
    events.push_back({e->eventnum, e->timestamp, e->channel, {bytes, bytes + e->datalen}});
  }
  struct stat st {};
  *damaged = ::stat(path.c_str(), &st) != 0 || stopped_at < st.st_size;
  return events;
}

void ExpectEvents(const std::vector<LogEvent>& events, int count) {
  ASSERT_EQ(static_cast<int>(events.size()), count);
  for (int k = 0; k < count; ++k) {
    EXPECT_EQ(events[static_cast<std::size_t>(k)].event_number, k);
    EXPECT_EQ(events[static_cast<std::size_t>(k)].timestamp_utime, 1000 * (k + 1));
    EXPECT_EQ(events[static_cast<std::size_t>(k)].channel, "CH" + std::to_string(k % 3));
    EXPECT_EQ(events[static_cast<std::size_t>(k)].data, Payload(k)) << "event " << k;
  }
}

std::int64_t FileSize(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? static_cast<std::int64_t>(st.st_size) : -1;
}

TEST(LogFileAppender, WritesWhatLcmsReaderReads) {
  const std::string path = TempPath("plain");
  std::remove(path.c_str());
  std::string error;
  auto file = LogFileAppender::Open(path, nullptr, &error);
  ASSERT_NE(file, nullptr) << error;
  AppendEvents(file.get(), 0, 50);
  ASSERT_TRUE(file->Flush(&error)) << error;
  EXPECT_EQ(file->pending_events(), 0);
  EXPECT_EQ(file->file_bytes(), FileSize(path));
  bool damaged = true;
  ExpectEvents(ReadAll(path, &damaged), 50);
  EXPECT_FALSE(damaged);
  std::remove(path.c_str());
}

TEST(LogFileAppender, ResumesAKilledWritersFileCuttingOnlyItsTornLastEvent) {
  const std::string path = TempPath("resume");
  std::remove(path.c_str());
  std::string error;
  std::int64_t whole = 0;
  {
    auto file = LogFileAppender::Open(path, nullptr, &error);
    ASSERT_NE(file, nullptr) << error;
    AppendEvents(file.get(), 0, 20);
    ASSERT_TRUE(file->Flush(&error));
    whole = file->file_bytes();
  }
  // A kill mid-write: the first 37 bytes of event 20 reached the disk.
  {
    auto file = LogFileAppender::Open(path, nullptr, &error);
    ASSERT_NE(file, nullptr) << error;
    AppendEvents(file.get(), 20, 21);
    ASSERT_TRUE(file->Flush(&error));
  }
  ASSERT_EQ(::truncate(path.c_str(), whole + 37), 0);
  bool damaged = false;
  ReadAll(path, &damaged);
  ASSERT_TRUE(damaged) << "the torn event is damage to LCM's reader";

  LogResume resume;
  auto file = LogFileAppender::Open(path, &resume, &error);
  ASSERT_NE(file, nullptr) << error;
  EXPECT_EQ(resume.events, 20);
  EXPECT_EQ(resume.torn_bytes, 37);
  AppendEvents(file.get(), 20, 30);  // numbering continues at 20
  ASSERT_TRUE(file->Flush(&error)) << error;
  ExpectEvents(ReadAll(path, &damaged), 30);
  EXPECT_FALSE(damaged);
  std::remove(path.c_str());
}

TEST(LogFileAppender, RefusesAFileDamagedBeforeItsEnd) {
  const std::string path = TempPath("inside");
  std::remove(path.c_str());
  std::string error;
  std::int64_t size = 0;
  {
    auto file = LogFileAppender::Open(path, nullptr, &error);
    AppendEvents(file.get(), 0, 10);
    ASSERT_TRUE(file->Flush(&error));
    size = file->file_bytes();
  }
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(size / 2);
    f.write("garbage!", 8);
  }
  auto file = LogFileAppender::Open(path, nullptr, &error);
  EXPECT_EQ(file, nullptr);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("damaged at byte"), std::string::npos) << error;
  EXPECT_EQ(FileSize(path), size) << "a damaged log is left as it was";
  std::remove(path.c_str());
}

// The file-size limit of this process stands in for a full disk: writes past
// it fail (EFBIG; SIGXFSZ ignored), like ENOSPC on a full filesystem.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::signal(SIGXFSZ, SIG_IGN);
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    rlimit limited = saved_;
    limited.rlim_cur = bytes;
    ok_ = ::setrlimit(RLIMIT_FSIZE, &limited) == 0;
  }
  ~FileSizeLimit() { Lift(); }
  void Lift() { ::setrlimit(RLIMIT_FSIZE, &saved_); }
  bool ok() const { return ok_; }

 private:
  rlimit saved_{};
  bool ok_ = false;
};

TEST(LogFileAppender, AFullDiskLeavesAWholeEventEndAndLosesNothingOnceThereIsRoom) {
  const std::string path = TempPath("full");
  std::remove(path.c_str());
  std::string error;
  auto file = LogFileAppender::Open(path, nullptr, &error);
  ASSERT_NE(file, nullptr) << error;
  FileSizeLimit limit(4000);
  ASSERT_TRUE(limit.ok());
  AppendEvents(file.get(), 0, 60);  // about 10 kB
  EXPECT_FALSE(file->Flush(&error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("File too large"), std::string::npos) << error;
  EXPECT_GT(file->pending_events(), 0);
  EXPECT_LE(file->file_bytes(), 4000);
  EXPECT_EQ(FileSize(path), file->file_bytes()) << "the torn event must be cut";
  bool damaged = true;
  const auto on_disk = ReadAll(path, &damaged);
  EXPECT_FALSE(damaged) << "a full disk must leave a readable file";
  EXPECT_EQ(static_cast<std::int64_t>(on_disk.size()) + file->pending_events(), 60);

  EXPECT_FALSE(file->Flush(&error)) << "still full";
  limit.Lift();  // room again
  ASSERT_TRUE(file->Flush(&error)) << error;
  ExpectEvents(ReadAll(path, &damaged), 60);
  EXPECT_FALSE(damaged);
  std::remove(path.c_str());
}

// A tmpfs of `kilobytes`, mounted at `dir` in this process's own mount
// namespace (nobody else sees it); false where that is not permitted.
bool MountPrivateTmpfs(const std::string& dir, int kilobytes, std::string* why) {
  if (::unshare(CLONE_NEWNS) != 0 || ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) {
    *why = std::string("a private mount namespace needs root: ") + std::strerror(errno);
    return false;
  }
  ::mkdir(dir.c_str(), 0755);
  if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, ("size=" + std::to_string(kilobytes) + "k").c_str()) != 0) {
    *why = std::string("mount tmpfs: ") + std::strerror(errno);
    return false;
  }
  return true;
}

// Writes `path` until the filesystem refuses another byte.
void FillDisk(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  const std::vector<char> block(4096, 'x');
  while (std::fwrite(block.data(), 1, block.size(), f) == block.size() && std::fflush(f) == 0) {
  }
  std::fclose(f);
}

// Counts the changes to a file (writes, cuts) from when it was made.
class FileChanges {
 public:
  explicit FileChanges(const std::string& path) : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
    ::inotify_add_watch(fd_, path.c_str(), IN_MODIFY);
  }
  ~FileChanges() { ::close(fd_); }
  int count() const {
    alignas(inotify_event) char buffer[4096];
    int changes = 0;
    for (ssize_t n; (n = ::read(fd_, buffer, sizeof buffer)) > 0;) {
      for (ssize_t at = 0; at < n; ++changes)
        at += static_cast<ssize_t>(sizeof(inotify_event)) + reinterpret_cast<inotify_event*>(buffer + at)->len;
    }
    return changes;
  }

 private:
  int fd_;
};

// A real full disk: a flush that finds no room leaves the file untouched (no
// write to cut back, so a reader can never catch a torn event, not even for
// an instant); a little room takes the whole events that fit; the rest goes
// once there is room.
TEST(LogFileAppender, OnARealFullDiskTheFileOnlyEverGainsWholeEvents) {
  const std::string dir = test_support::ScratchRoot() + "/appender_tmpfs";
  std::string why;
  if (!MountPrivateTmpfs(dir, 256, &why)) GTEST_SKIP() << why;
  const std::string path = dir + "/run.lcmlog";
  std::string error;
  auto file = LogFileAppender::Open(path, nullptr, &error);
  ASSERT_NE(file, nullptr) << error;
  FillDisk(dir + "/filler");
  AppendEvents(file.get(), 0, 60);  // about 10 kB

  FileChanges no_room(path);
  EXPECT_FALSE(file->Flush(&error));
  EXPECT_NE(error.find("No space left on device"), std::string::npos) << error;
  EXPECT_EQ(file->pending_events(), 60);
  EXPECT_EQ(no_room.count(), 0) << "a flush with no room wrote or cut the file";

  ASSERT_EQ(::truncate((dir + "/filler").c_str(), FileSize(dir + "/filler") - 2 * 4096), 0);  // a little room
  EXPECT_FALSE(file->Flush(&error)) << "8 kB free, less the page the filesystem keeps, cannot take 10 kB";
  EXPECT_GT(file->file_bytes(), 0) << "the whole events that fit were not written";
  ASSERT_NE(file->file_bytes() % 4096, 0) << "the file must end inside a page for this check to bite";
  EXPECT_EQ(FileSize(path), file->file_bytes());
  FileChanges full_again(path);
  EXPECT_FALSE(file->Flush(&error));
  EXPECT_EQ(full_again.count(), 0) << "a flush into the last page's remainder wrote (and cut) a torn event";
  bool damaged = true;
  EXPECT_EQ(static_cast<std::int64_t>(ReadAll(path, &damaged).size()) + file->pending_events(), 60);
  EXPECT_FALSE(damaged);

  std::remove((dir + "/filler").c_str());
  ASSERT_TRUE(file->Flush(&error)) << error;
  ExpectEvents(ReadAll(path, &damaged), 60);
  EXPECT_FALSE(damaged);
  file.reset();
  ::umount2(dir.c_str(), MNT_DETACH);
}

TEST(LogFileAppender, DropsTheNewestPendingEventsAboveABound) {
  const std::string path = TempPath("drop");
  std::remove(path.c_str());
  std::string error;
  auto file = LogFileAppender::Open(path, nullptr, &error);
  ASSERT_NE(file, nullptr) << error;
  AppendEvents(file.get(), 0, 10);
  const std::int64_t all = file->pending_bytes();
  const std::int64_t dropped = file->DropPendingAbove(all / 2);
  EXPECT_GT(dropped, 0);
  EXPECT_LE(file->pending_bytes(), all / 2);
  EXPECT_EQ(file->pending_events() + dropped, 10);
  ASSERT_TRUE(file->Flush(&error));
  bool damaged = true;
  ExpectEvents(ReadAll(path, &damaged), static_cast<int>(10 - dropped));  // the oldest kept
  EXPECT_FALSE(damaged);
  std::remove(path.c_str());
}

// The writer thread over it: a restarted logger (same --output file) appends.
TEST(LogWriter, ARestartedWriterAppendsToItsFileInsteadOfTruncatingIt) {
  const std::string path = TempPath("writer");
  std::remove(path.c_str());
  for (int run = 0; run < 2; ++run) {
    LogWriterOptions options;
    options.output = path;
    options.flush_ms = 5;
    LogWriter writer(options);
    EXPECT_EQ(writer.stats().resumed_events, run * 25);
    for (int k = run * 25; k < run * 25 + 25; ++k) {
      const auto bytes = Payload(k);
      ASSERT_TRUE(writer.Enqueue("CH" + std::to_string(k % 3), bytes.data(), static_cast<std::uint32_t>(bytes.size()),
                                 1000 * (k + 1)));
    }
  }
  bool damaged = true;
  ExpectEvents(ReadAll(path, &damaged), 50);
  EXPECT_FALSE(damaged);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace edsp
