// The log reader against logs written by LCM's own writer (an independent
// implementation of the format), cut at every byte: a log reads as damaged
// unless the cut falls exactly between two events, and it is read up to the
// last whole event.
#include "edsp/logger/log_reader.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include "scratch_dir.h"

namespace edsp {
namespace {

struct WrittenLog {
  std::string path;
  std::vector<std::int64_t> event_ends;  // bytes from the start of the file
};

// Events of varied sizes and channel names, as LCM's writer lays them out.
WrittenLog WriteWithLcm(const std::string& name, int count) {
  WrittenLog log{test_support::ScratchRoot() + "/reader_" + name + ".lcmlog", {}};
  std::remove(log.path.c_str());
  lcm::LogFile file(log.path, "w");
  for (int k = 0; k < count; ++k) {
    std::vector<std::uint8_t> data(static_cast<std::size_t>(1 + (k * 37) % 90), static_cast<std::uint8_t>(k));
    lcm::LogEvent e;
    e.eventnum = k;
    e.timestamp = 1000 * (k + 1);
    e.channel = "CH" + std::string(static_cast<std::size_t>(k % 4), 'X');
    e.datalen = static_cast<std::int32_t>(data.size());
    e.data = data.data();
    file.writeEvent(&e);
    std::fflush(file.getFilePtr());
    log.event_ends.push_back(static_cast<std::int64_t>(std::ftell(file.getFilePtr())));
  }
  return log;
}

struct ReadBack {
  std::int64_t events = 0;
  bool damaged = false;
  std::int64_t damage_offset = -1;
};

std::vector<char> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

ReadBack ReadAll(const std::string& path) {
  LogReader reader(path);
  ReadBack r;
  LogEvent e;
  while (reader.Next(&e)) ++r.events;
  r.damaged = reader.damaged();
  r.damage_offset = reader.damage_offset();
  return r;
}

TEST(LogReader, AWholeLogReadsEveryEventUndamaged) {
  const WrittenLog log = WriteWithLcm("whole", 20);
  const ReadBack r = ReadAll(log.path);
  EXPECT_EQ(r.events, 20);
  EXPECT_FALSE(r.damaged);
  std::remove(log.path.c_str());
}

// Every cut inside the last three events: a cut inside the next event's
// four sync bytes is the case LCM's reader takes for a clean end.
TEST(LogReader, ALogCutAtAnyByteInsideAnEventReadsAsDamagedAfterTheLastWholeEvent) {
  const WrittenLog log = WriteWithLcm("cut", 12);
  const std::int64_t size = log.event_ends.back();
  const std::int64_t from = log.event_ends[log.event_ends.size() - 4];
  const std::vector<char> bytes = ReadBytes(log.path);
  ASSERT_EQ(static_cast<std::int64_t>(bytes.size()), size);
  const std::string cut = log.path + ".cut";
  for (std::int64_t at = from; at < size; ++at) {
    std::ofstream(cut, std::ios::binary | std::ios::trunc).write(bytes.data(), at);
    std::int64_t whole = 0, whole_end = 0;
    for (const std::int64_t end : log.event_ends) {
      if (end > at) break;
      ++whole;
      whole_end = end;
    }
    const ReadBack r = ReadAll(cut);
    EXPECT_EQ(r.events, whole) << "cut at byte " << at;
    EXPECT_EQ(r.damaged, whole_end != at) << "cut at byte " << at << ", last whole event ends at " << whole_end;
    if (r.damaged) {
      EXPECT_EQ(r.damage_offset, whole_end) << "cut at byte " << at;
    }
  }
  std::remove(cut.c_str());
  std::remove(log.path.c_str());
}

}  // namespace
}  // namespace edsp
