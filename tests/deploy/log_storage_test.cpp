// The log's storage under a moving sim group (label multiprocess, private
// network and mount namespaces): a disk that fills up mid-run, and a log cut
// short. The logger reports a full disk on EDSP_FAULT and EDSP_STATUS, keeps
// its file readable to the last whole event at every moment, holds what it
// cannot write in memory up to its bound (then drops, counted), and writes
// again once there is room; the motion never notices. The tools read a
// truncated log up to the damage and say where it is.
#include <sched.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/fault_t.hpp"
#include "edsp/kinematics/config.h"
#include "edsp/logger/log_reader.h"
#include "edsp/node/fault.h"
#include "edsp/node/runtime.h"
#include "edsp/node_status_t.hpp"
#include "late_cycles.h"  // tests/support
#include "edsp/tracker_point_t.hpp"
#include "edsp/transport/seq_gap.h"
#include "sim_group_harness.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

using namespace test_support;  // sim_group_harness.h

// A small tmpfs of this test's own (a private mount namespace: the launcher
// and the nodes see it, nobody else does, and it vanishes with the test).
void MountSmallDisk(const std::string& path, const std::string& size) {
  ASSERT_EQ(::unshare(CLONE_NEWNS), 0) << "unshare(CLONE_NEWNS) needs root: " << std::strerror(errno);
  ASSERT_EQ(::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr), 0) << std::strerror(errno);
  std::system(("mkdir -p " + path).c_str());
  ASSERT_EQ(::mount("tmpfs", path.c_str(), "tmpfs", 0, ("size=" + size).c_str()), 0) << std::strerror(errno);
}

std::int64_t FreeBytes(const std::string& path) {
  struct statvfs s {};
  if (::statvfs(path.c_str(), &s) != 0) return -1;
  return static_cast<std::int64_t>(s.f_bavail) * static_cast<std::int64_t>(s.f_frsize);
}

std::int64_t FileSize(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? static_cast<std::int64_t>(st.st_size) : -1;
}

bool ReadsWhole(const std::string& path, std::int64_t* events) {
  LogReader reader(path);
  LogEvent e;
  *events = 0;
  while (reader.Next(&e)) ++*events;
  return !reader.damaged();
}

TEST(LogStorage, AFullDiskIsReportedKeepsTheLogReadableAndRecoversWhenThereIsRoom) {
  const std::string dir = test_support::SimGroupDir("diskfull");
  const std::string disk = dir + "/disk";
  // 63.5 MB of 64 taken: the log has about 0.5 MB (under a second) before
  // the disk is full; once the filler goes, room for the rest of the run
  // (about 1 MB a second of log, however long a slow machine makes it:
  // with only a few MB the disk filled again and the later dwells went
  // unrecorded).
  MountSmallDisk(disk, "64m");
  {
    std::ofstream filler(disk + "/filler", std::ios::binary);
    const std::string block(1 << 20, '\0');
    for (int k = 0; k < 63; ++k) filler << block;
    filler << block.substr(0, 1 << 19);
  }
  const std::string log = disk + "/run.lcmlog";
  SimGroupExtras extras;
  extras.log_path = log;
  extras.edit = [](GroupFileEditor& g) { g.AppendArgs("logger", {"--max-queue-mb", "1", "--flush-ms", "50"}); };
  std::int64_t full_utime = 0, freed_utime = 0, events_while_full = 0;
  bool whole_while_full = false;
  const GroupRun run = LaunchSimGroup(
      "diskfull", "signed",
      R"("--motions", "Lz", "--stops", "2", "--dwell-s", "1", "--max-speed-m-s", "0.25", "--exit-after-hold-s", "0.5")",
      [&](const std::string&) {
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (FreeBytes(disk) > 64 * 1024 && std::chrono::steady_clock::now() < give_up) {
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        full_utime = UtimeNow();
        std::this_thread::sleep_for(std::chrono::milliseconds(1000));
        // While the disk is full, the log as it is on disk reads to its end.
        whole_while_full = ReadsWhole(log, &events_while_full);
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        std::remove((disk + "/filler").c_str());
        freed_utime = UtimeNow();
      },
      77, test_support::kDefaultConfig, test_support::kStallTolerantStaleMs, extras);
  std::ifstream launch_err(dir + "/launch.err");
  std::ostringstream launch_text;
  launch_text << launch_err.rdbuf();
  ASSERT_EQ(run.exit_code, 0) << launch_text.str();
  ASSERT_GT(full_utime, 0);
  EXPECT_TRUE(whole_while_full) << "a full disk left a torn event in the log";
  EXPECT_GT(events_while_full, 1000);

  LogReader reader(log);
  LogEvent e;
  std::int64_t events = 0, after_freed = 0, tracker_gaps = 0, last_tracker_seq = -1;
  std::int64_t full_fault_utime = 0, recovered_utime = 0, first_after_freed = 0;
  bool status_fault = false;
  std::string full_reason, recovered_reason;
  while (reader.Next(&e)) {
    ++events;
    const int size = static_cast<int>(e.data.size());
    if (e.timestamp_utime > freed_utime && ++after_freed == 1) first_after_freed = e.timestamp_utime;
    if (e.channel == "EDSP_FAULT") {
      fault_t f;
      if (f.decode(e.data.data(), 0, size) < 0 || f.node != "logger") continue;
      if (f.code != static_cast<std::int32_t>(FaultCode::kStorage)) continue;
      if (f.severity == fault_t::SEVERITY_ERROR && full_fault_utime == 0) {
        full_fault_utime = f.utime;
        full_reason = f.reason;
      }
      if (f.severity == fault_t::SEVERITY_INFO && f.utime > freed_utime) {
        recovered_utime = f.utime;
        recovered_reason = f.reason;
      }
    } else if (e.channel == "EDSP_STATUS") {
      node_status_t s;
      if (s.decode(e.data.data(), 0, size) >= 0 && s.node == "logger" && s.state == node_status_t::STATE_FAULT) {
        status_fault = true;
      }
    } else if (e.channel == "EDSP_TRACKER") {
      tracker_point_t t;
      if (t.decode(e.data.data(), 0, size) < 0) continue;
      tracker_gaps += SeqGap(last_tracker_seq, t.seq);
      last_tracker_seq = t.seq;
    }
  }
  EXPECT_FALSE(reader.damaged()) << "damaged at byte " << reader.damage_offset();
  // Reported: the error names the file and the reason, while it happened
  // (logged after the room came back: the fault waited in memory).
  ASSERT_GT(full_fault_utime, 0) << "no storage fault from the logger";
  EXPECT_NE(full_reason.find(log), std::string::npos) << full_reason;
  EXPECT_NE(full_reason.find("No space left on device"), std::string::npos) << full_reason;
  EXPECT_TRUE(status_fault) << "the logger's EDSP_STATUS never said fault";
  ASSERT_GT(recovered_utime, 0) << "no recovery report from the logger";
  EXPECT_NE(recovered_reason.find("writing again"), std::string::npos) << recovered_reason;
  // Recovered: everything after the room came back is there, and the loss
  // is what the memory bound could not hold (1 MB: about a second).
  EXPECT_GT(after_freed, 5000);
  EXPECT_GT(tracker_gaps, 0) << "2.5 s full with 1 MB of memory must drop something";
  // The motion never noticed: every dwell lands. Unless the machine made
  // the bridge hold (a loop feeding it late by half its stale limit, the
  // rig's drives silent by half their timeout: late_cycles.h), never the
  // full disk; a machine that cannot run the group in real time (a
  // sanitized group at half speed) cannot then show the dwells.
  // While the disk was full the logger dropped what its memory could not
  // hold: a latch then has no log of the command chain around it to read
  // the machine's lateness from (the bridge latches only on commands it did
  // not get, and the disk is on no node's command path).
  if (const std::optional<std::int64_t> latch = test_support::FirstBridgeLatchUtime(log)) {
    const bool unlogged = *latch >= full_utime && *latch <= first_after_freed;
    const test_support::LatenessAroundTheBridge late = test_support::LatenessAroundTheBridgeWithin(log, 0, *latch);
    std::printf("the bridge latched %.3f s after the disk filled; %s%s\n",
                static_cast<double>(*latch - full_utime) * 1e-6, late.Describe().c_str(),
                unlogged ? " (while the logger dropped: unverifiable from the log)" : "");
    if (!unlogged) {
      EXPECT_TRUE(late.ExplainsALatch(std::int64_t{test_support::kShippedStaleMs} * 1000))
          << "the bridge latched with no stall to explain it: " << late.Describe();
    }
  } else {
    const auto ends = DwellEnds(log, PlatformModel(Huang2021Config()));
    ASSERT_FALSE(ends.empty());
    for (const DwellEnd& d : ends) EXPECT_LT(d.miss_m, 5e-6) << d.segment;
  }
  std::printf(
      "STORAGE_ROW | disk full 2.5 s (64 MB tmpfs, 1 MB memory) | report %.1f ms | recover %.1f ms | "
      "%lld events, %lld tracker samples lost | %s | %s\n",
      static_cast<double>(full_fault_utime - full_utime) * 1e-3,
      static_cast<double>(first_after_freed - freed_utime) * 1e-3, static_cast<long long>(events),
      static_cast<long long>(tracker_gaps), full_reason.c_str(), recovered_reason.c_str());
  ::umount2(disk.c_str(), MNT_DETACH);
}

int RunTool(const std::string& args, const std::string& out, std::string* text) {
  const int status = std::system(fmt::format("{} {} >{} 2>&1", BuiltProgram("edsp-log"), args, out).c_str());
  std::ifstream in(out);
  std::ostringstream s;
  s << in.rdbuf();
  *text = s.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A log cut mid-event (a power cut, a copy interrupted): every tool reads
// what precedes the damage, says at which byte it is, and exits 3.
TEST(LogStorage, ATruncatedLogIsReadUpToTheDamageByEveryTool) {
  const GroupRun run = LaunchSimGroup(
      "truncated", "signed",
      R"("--motions", "Lz", "--stops", "2", "--dwell-s", "0.3", "--max-speed-m-s", "0.5", "--exit-after-hold-s", "0")");
  ASSERT_EQ(run.exit_code, 0);
  const std::string cut = run.dir + "/cut.lcmlog";
  std::system(fmt::format("cp {} {}", run.log_path, cut).c_str());
  const std::int64_t size = FileSize(cut);
  ASSERT_GT(size, 100000);
  // Cut in the middle of an event, 60% in: should that byte happen to end
  // an event, one byte less is inside it.
  const std::int64_t first_cut = size * 6 / 10 + 7;
  std::int64_t at = first_cut, whole_events = 0;
  bool damaged = false;
  while (!damaged && at >= first_cut - 1) {
    ASSERT_EQ(::truncate(cut.c_str(), at), 0);
    LogReader reader(cut);
    LogEvent e;
    whole_events = 0;
    while (reader.Next(&e)) ++whole_events;
    damaged = reader.damaged();
    if (!damaged) {
      --at;
      continue;
    }
    EXPECT_LE(reader.damage_offset(), at);
    EXPECT_GT(reader.damage_offset(), at - 2000);
  }
  ASSERT_TRUE(damaged) << "a log cut inside an event must read as damaged";
  std::string text;
  EXPECT_EQ(RunTool("info --json " + cut, run.dir + "/info.out", &text), 3) << text;
  EXPECT_NE(text.find("\"damaged\": true"), std::string::npos) << text;
  EXPECT_NE(text.find("damage_offset_bytes"), std::string::npos) << text;
  EXPECT_EQ(RunTool("faults " + cut, run.dir + "/faults.out", &text), 3) << text;
  EXPECT_NE(text.find("damaged at byte"), std::string::npos) << text;
  EXPECT_EQ(RunTool(fmt::format("export --csv {}/csv --channels EDSP_TRACKER {}", run.dir, cut),
                    run.dir + "/export.out", &text),
            3)
      << text;
  EXPECT_NE(text.find(cut), std::string::npos) << "the message names the file: " << text;
  // The CSV holds the tracker samples that precede the damage.
  std::ifstream csv(run.dir + "/csv/EDSP_TRACKER.csv");
  std::string line;
  std::int64_t rows = -1;  // the header
  while (std::getline(csv, line)) ++rows;
  EXPECT_GT(rows, 1000);
  // lcm-logplayer (LCM's own tool) plays it to the damage without failing.
  EXPECT_EQ(
      std::system(
          fmt::format("lcm-logplayer -s 100 -l 'udpm://239.255.76.67:7667?ttl=0' {} >/dev/null 2>&1", cut).c_str()),
      0);
  std::printf("TRUNCATED_ROW | log of %lld bytes cut at byte %lld | %lld whole events read | tracker rows %lld\n",
              static_cast<long long>(size), static_cast<long long>(at), static_cast<long long>(whole_events),
              static_cast<long long>(rows));
}

}  // namespace
}  // namespace edsp
