// LoggerNode and DiskHealth in process: what edsp-logger records, from LCM
// and from shared memory, what it counts as lost, and what it reports.
#include "edsp/logger/logger_node.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/logger/log_reader.h"
#include "edsp/node/fault.h"
#include "memq_bus.h"
#include "scratch_dir.h"

namespace edsp {
namespace {

using test_support::MemqConfig;
using test_support::ScratchDir;

leg_command_t Command(std::int64_t seq) {
  leg_command_t c{};
  c.utime = 1000 + seq;
  c.seq = seq;
  c.session_id = 7;
  c.command_length_m[0] = 0.5 + 1e-6 * static_cast<double>(seq);
  return c;
}

// The seq numbers recorded on `channel`, read back from the closed log.
std::vector<std::int64_t> RecordedSeqs(const std::string& path, const std::string& channel) {
  std::vector<std::int64_t> seqs;
  LogReader reader(path);
  LogEvent event;
  while (reader.Next(&event)) {
    if (event.channel != channel) continue;
    EdspHeader header;  // any edsp type: utime and seq lead every message
    EXPECT_TRUE(ParseEdspHeader(event.data, &header)) << "recorded bytes hold a message";
    seqs.push_back(header.seq);
  }
  EXPECT_FALSE(reader.damaged());
  return seqs;
}

// What a writer's LCM mirror (or a writer elsewhere) puts on the bus.
void PublishOnLcm(Bus& bus, const leg_command_t& c) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(c.getEncodedSize()));
  c.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  ASSERT_TRUE(bus.lcm().Publish("EDSP_LEG_COMMAND", bytes.data(), static_cast<std::uint32_t>(bytes.size())));
}

// The reasons of the transport faults the logger recorded of itself.
std::vector<std::string> TransportFaults(const std::string& path) {
  LogReader reader(path);
  LogEvent event;
  std::vector<std::string> reasons;
  while (reader.Next(&event)) {
    fault_t fault;
    if (event.channel != "EDSP_FAULT" || fault.decode(event.data.data(), 0, static_cast<int>(event.data.size())) < 0) {
      continue;
    }
    if (fault.code == static_cast<std::int32_t>(FaultCode::kTransport)) reasons.push_back(fault.reason);
  }
  return reasons;
}

// first, first + 1, ..., last: what a writer published, every one.
std::vector<std::int64_t> Seqs(std::int64_t first, std::int64_t last) {
  std::vector<std::int64_t> seqs;
  for (std::int64_t seq = first; seq <= last; ++seq) seqs.push_back(seq);
  return seqs;
}

void HandleAll(Bus& bus, LoggerNode& logger) {
  while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
  }
  logger.Poll(UtimeNow());
}

LoggerOptions OptionsFor(const std::string& name) {
  LoggerOptions options;
  options.writer.output = ScratchDir("logger_node") + "/" + name + ".lcmlog";
  return options;
}

TEST(LoggerNode, RecordsLcmChannelsAndCountsWhatEachLostBySeq) {
  Bus bus(MemqConfig("logger_lcm"));
  const LoggerOptions options = OptionsFor("lcm");
  std::int64_t lost = 0;
  {
    LoggerNode logger(bus, options);
    EXPECT_TRUE(logger.shm_channels().empty());
    for (std::int64_t seq = 0; seq < 100; ++seq) {
      if (seq == 40 || seq == 41 || seq == 77) continue;  // three lost on the way
      bus.Publish("EDSP_LEG_COMMAND", Command(seq));
    }
    bus.Publish("OTHER_CHANNEL", Command(0));  // not EDSP_.*: not recorded
    HandleAll(bus, logger);
    lost = logger.lost();
  }
  EXPECT_EQ(lost, 3);
  const std::vector<std::int64_t> seqs = RecordedSeqs(options.writer.output, "EDSP_LEG_COMMAND");
  ASSERT_EQ(seqs.size(), 97u);
  EXPECT_EQ(seqs.front(), 0);
  EXPECT_EQ(seqs.back(), 99);
  EXPECT_TRUE(RecordedSeqs(options.writer.output, "OTHER_CHANNEL").empty());
}

// A channel routed only on shared memory never reaches LCM: the logger must
// read it there, every message, and one routed both ways (a decimated LCM
// mirror) once, not once more per mirrored message.
TEST(LoggerNode, RecordsEveryMessageOfChannelsRoutedOnSharedMemory) {
  TransportConfig config = MemqConfig("logger_shm");
  config.channels["EDSP_LEG_COMMAND"].path = ChannelPath::kShm;
  ChannelRoute& both = config.channels["EDSP_LEG_STATE"];
  both.path = ChannelPath::kBoth;
  both.mirror_every = 10;
  Bus bus(config);
  const LoggerOptions options = OptionsFor("shm");
  std::int64_t lost = -1;
  // The writers first: a reader that finds no segment looks again every 10 ms.
  auto commands = bus.Advertise<leg_command_t>("EDSP_LEG_COMMAND");
  auto states = bus.Advertise<leg_state_t>("EDSP_LEG_STATE");
  {
    LoggerNode logger(bus, options);
    EXPECT_EQ(logger.shm_channels(), (std::vector<std::string>{"EDSP_LEG_COMMAND", "EDSP_LEG_STATE"}));
    for (std::int64_t seq = 0; seq < 1000; ++seq) {
      ASSERT_TRUE(commands.Publish(Command(seq)));
      leg_state_t state{};
      state.seq = seq;
      ASSERT_TRUE(states.Publish(state));
      if (seq % 16 == 15) HandleAll(bus, logger);  // well inside the 64-slot rings
    }
    HandleAll(bus, logger);
    EXPECT_EQ(bus.Counters("EDSP_LEG_STATE").mirrored, 100u) << "the mirror went out on LCM";
    lost = logger.lost();
  }
  EXPECT_EQ(lost, 0);
  for (const char* channel : {"EDSP_LEG_COMMAND", "EDSP_LEG_STATE"}) {
    const std::vector<std::int64_t> seqs = RecordedSeqs(options.writer.output, channel);
    ASSERT_EQ(seqs.size(), 1000u) << channel;
    for (std::size_t i = 0; i < seqs.size(); ++i) ASSERT_EQ(seqs[i], static_cast<std::int64_t>(i)) << channel;
  }
}

// A logger that falls more than a ring behind loses the oldest messages: it
// records what is left, in order, and counts the rest as lost.
TEST(LoggerNode, CountsWhatALappedSharedMemoryReadLost) {
  TransportConfig config = MemqConfig("logger_lapped");
  config.channels["EDSP_LEG_COMMAND"].path = ChannelPath::kShm;
  Bus bus(config);
  const LoggerOptions options = OptionsFor("lapped");
  std::int64_t lost = -1;
  auto commands = bus.Advertise<leg_command_t>("EDSP_LEG_COMMAND");
  {
    LoggerNode logger(bus, options);
    for (std::int64_t seq = 0; seq < 200; ++seq) ASSERT_TRUE(commands.Publish(Command(seq)));
    HandleAll(bus, logger);
    lost = logger.lost();
  }
  const std::vector<std::int64_t> seqs = RecordedSeqs(options.writer.output, "EDSP_LEG_COMMAND");
  ASSERT_EQ(seqs.size(), 64u);
  EXPECT_EQ(seqs.front(), 136);
  EXPECT_EQ(seqs.back(), 199);
  EXPECT_EQ(lost, 136);
}

// A logger that subscribed before the writer made its ring (the launch
// order puts the logger anywhere), or that sees a writer exit in order and
// a new one make the ring anew, records each writer's first messages too:
// they were all published after it subscribed.
TEST(LoggerNode, RecordsAWritersFirstMessagesWhenItsRingAppearsAfterTheLoggerSubscribed) {
  TransportConfig config = MemqConfig("logger_late_ring");
  config.channels["EDSP_LEG_COMMAND"].path = ChannelPath::kShm;
  Bus logger_bus(config);
  const LoggerOptions options = OptionsFor("late_ring");
  std::int64_t lost = -1;
  {
    LoggerNode logger(logger_bus, options);
    for (int writer = 0; writer < 2; ++writer) {
      {
        Bus writer_bus(config);  // another process's Bus: its own memq, the same rings
        auto commands = writer_bus.Advertise<leg_command_t>("EDSP_LEG_COMMAND");
        for (std::int64_t seq = 0; seq < 10; ++seq) ASSERT_TRUE(commands.Publish(Command(100 * writer + seq)));
        // The logger looks again for a missing or abandoned ring every 10 ms.
        for (int pass = 0; pass < 3; ++pass) {
          std::this_thread::sleep_for(std::chrono::milliseconds(60));
          HandleAll(logger_bus, logger);
        }
      }  // the writer exits in order: its ring is removed
      HandleAll(logger_bus, logger);
    }
    lost = logger.lost();
  }
  const std::vector<std::int64_t> seqs = RecordedSeqs(options.writer.output, "EDSP_LEG_COMMAND");
  std::vector<std::int64_t> expected;
  for (std::int64_t writer = 0; writer < 2; ++writer) {
    for (std::int64_t seq = 0; seq < 10; ++seq) expected.push_back(100 * writer + seq);
  }
  EXPECT_EQ(seqs, expected);
  EXPECT_EQ(lost, 0);
}

// A channel routed `both`: its writer's LCM mirror (every 10th message) can
// reach the logger before the logger finds the ring (the writer started
// after it, as the planner does). Recording those copies and then the ring
// from its first message would record them twice (a 10-minute sim run
// logged setpoints 10, 20, 30, 40, 1, 2, ...: 27 "lost" that were not).
// The ring has every message once: that is what is recorded, none lost.
TEST(LoggerNode, AMirrorThatArrivesBeforeItsRingIsNotRecordedTwice) {
  TransportConfig config = MemqConfig("logger_mirror_first");
  config.channels["EDSP_LEG_COMMAND"].path = ChannelPath::kBoth;
  config.channels["EDSP_LEG_COMMAND"].mirror_every = 10;
  Bus logger_bus(config);
  const LoggerOptions options = OptionsFor("mirror_first");
  std::int64_t lost = -1;
  {
    LoggerNode logger(logger_bus, options);
    for (std::int64_t seq : {10, 20}) PublishOnLcm(logger_bus, Command(seq));  // the mirror's, ahead of the ring
    HandleAll(logger_bus, logger);
    Bus writer_bus(config);  // another process's Bus: its own memq, the same ring
    auto commands = writer_bus.Advertise<leg_command_t>("EDSP_LEG_COMMAND");
    for (std::int64_t seq = 1; seq <= 25; ++seq) ASSERT_TRUE(commands.Publish(Command(seq)));
    for (int pass = 0; pass < 3; ++pass) {  // the logger looks again for a missing ring every 10 ms
      std::this_thread::sleep_for(std::chrono::milliseconds(60));
      HandleAll(logger_bus, logger);
    }
    lost = logger.lost();
  }
  EXPECT_EQ(RecordedSeqs(options.writer.output, "EDSP_LEG_COMMAND"), Seqs(1, 25));
  EXPECT_EQ(lost, 0);
}

// A `both` channel whose ring never comes to this host while its LCM
// copies do (a writer on another host that the group file does not say,
// or one that publishes on LCM only): waiting for the ring must not lose
// the channel silently. After 1 s of copies they are recorded, and said.
TEST(LoggerNode, LcmCopiesOfARingThatNeverComesAreRecordedAfterAGraceAndSaid) {
  TransportConfig config = MemqConfig("logger_no_ring");
  config.channels["EDSP_LEG_COMMAND"].path = ChannelPath::kBoth;
  Bus bus(config);
  const LoggerOptions options = OptionsFor("no_ring");
  {
    LoggerNode logger(bus, options);
    PublishOnLcm(bus, Command(1));  // within the grace: the ring may be coming
    HandleAll(bus, logger);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    for (std::int64_t seq : {2, 3}) PublishOnLcm(bus, Command(seq));
    HandleAll(bus, logger);
    HandleAll(bus, logger);  // the fault it published, recorded
  }
  EXPECT_EQ(RecordedSeqs(options.writer.output, "EDSP_LEG_COMMAND"), (std::vector<std::int64_t>{2, 3}));
  const std::vector<std::string> reasons = TransportFaults(options.writer.output);
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_NE(reasons[0].find("no ring written on this host after 1 s of LCM copies (1 skipped)"), std::string::npos)
      << reasons[0];
}

// A writer that starts after the logger fills its ring (64 slots, 64 ms at
// 1 kHz) before long: the logger must find the ring before its first
// message is overwritten (a look every 100 ms would lose a 1 kHz writer's
// first messages); here 80 messages, the first 30 of them before the
// logger has had 15 ms to look.
TEST(LoggerNode, FindsALateRingBeforeItsFirstMessagesAreOverwritten) {
  TransportConfig config = MemqConfig("logger_late_ring_fast");
  config.channels["EDSP_LEG_COMMAND"].path = ChannelPath::kShm;
  Bus logger_bus(config);
  const LoggerOptions options = OptionsFor("late_ring_fast");
  std::int64_t lost = -1;
  {
    LoggerNode logger(logger_bus, options);
    Bus writer_bus(config);
    auto commands = writer_bus.Advertise<leg_command_t>("EDSP_LEG_COMMAND");
    for (std::int64_t seq = 1; seq <= 30; ++seq) ASSERT_TRUE(commands.Publish(Command(seq)));
    std::this_thread::sleep_for(std::chrono::milliseconds(15));
    HandleAll(logger_bus, logger);
    for (std::int64_t seq = 31; seq <= 80; ++seq) ASSERT_TRUE(commands.Publish(Command(seq)));
    std::this_thread::sleep_for(std::chrono::milliseconds(110));  // past any look, however slow
    HandleAll(logger_bus, logger);
    lost = logger.lost();
  }
  EXPECT_EQ(RecordedSeqs(options.writer.output, "EDSP_LEG_COMMAND"), Seqs(1, 80));
  EXPECT_EQ(lost, 0);
}

// A ring the logger cannot read (here: not an edsp segment at all) must not
// silence the channel: its LCM copy is recorded, and the reason reported.
TEST(LoggerNode, AChannelWhoseRingCannotBeReadIsRecordedFromLcmAndReported) {
  TransportConfig config = MemqConfig("logger_bad_ring");
  config.channels["EDSP_LEG_COMMAND"].path = ChannelPath::kBoth;
  const std::string segment = "/dev/shm/" + config.SegmentName("EDSP_LEG_COMMAND");
  std::ofstream(segment) << std::string(8192, '\xab');
  Bus bus(config);
  const LoggerOptions options = OptionsFor("bad_ring");
  {
    LoggerNode logger(bus, options);
    PublishOnLcm(bus, Command(5));
    HandleAll(bus, logger);
    HandleAll(bus, logger);  // the fault it published, recorded
  }
  std::remove(segment.c_str());
  EXPECT_EQ(RecordedSeqs(options.writer.output, "EDSP_LEG_COMMAND"), (std::vector<std::int64_t>{5}));
  const std::vector<std::string> reasons = TransportFaults(options.writer.output);
  ASSERT_EQ(reasons.size(), 1u) << "one report per reason";
  EXPECT_NE(reasons[0].find("EDSP_LEG_COMMAND: cannot read its shared memory"), std::string::npos) << reasons[0];
  EXPECT_NE(reasons[0].find("recording its LCM copy"), std::string::npos) << reasons[0];
}

// A writer exits in order (its ring removed) and what takes the ring's
// place cannot be read: the logger says so and records the LCM copy, not
// nothing from a dead ring.
TEST(LoggerNode, ARestartedWritersUnreadableRingLeavesTheChannelItsLcmCopy) {
  TransportConfig config = MemqConfig("logger_bad_successor");
  config.channels["EDSP_LEG_COMMAND"].path = ChannelPath::kBoth;
  const std::string segment = "/dev/shm/" + config.SegmentName("EDSP_LEG_COMMAND");
  Bus logger_bus(config);
  const LoggerOptions options = OptionsFor("bad_successor");
  {
    LoggerNode logger(logger_bus, options);
    {
      Bus writer_bus(config);
      auto commands = writer_bus.Advertise<leg_command_t>("EDSP_LEG_COMMAND");
      ASSERT_TRUE(commands.Publish(Command(1)));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      HandleAll(logger_bus, logger);
    }                                                     // exits in order: the ring is removed
    std::ofstream(segment) << std::string(8192, '\xab');  // not an edsp segment
    for (int pass = 0; pass < 3; ++pass) {                // the dead ring noticed, the new one refused
      std::this_thread::sleep_for(std::chrono::milliseconds(40));
      HandleAll(logger_bus, logger);
    }
    PublishOnLcm(logger_bus, Command(2));
    HandleAll(logger_bus, logger);
    HandleAll(logger_bus, logger);
  }
  std::remove(segment.c_str());
  EXPECT_EQ(RecordedSeqs(options.writer.output, "EDSP_LEG_COMMAND"), (std::vector<std::int64_t>{1, 2}));
  const std::vector<std::string> reasons = TransportFaults(options.writer.output);
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_NE(reasons[0].find("cannot read its shared memory"), std::string::npos) << reasons[0];
}

TEST(LoggerNode, APatternThatIsNoRegexIsRefusedNamingIt) {
  Bus bus(MemqConfig("logger_bad_pattern"));
  LoggerOptions options = OptionsFor("bad_pattern");
  options.channels = "EDSP_(";
  try {
    LoggerNode logger(bus, options);
    FAIL() << "accepted " << options.channels;
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("not a POSIX extended regex"), std::string::npos) << e.what();
  }
}

LogWriterStats Disk(bool failing, std::int64_t dropped) {
  LogWriterStats w;
  w.path = "/rig/log.lcmlog";
  w.disk_failing = failing;
  w.dropped = dropped;
  w.last_error = "/rig/log.lcmlog: No space left on device";
  return w;
}

TEST(DiskHealth, ReportsAFullDiskOnceAndItsRecoveryWithWhatWasDropped) {
  DiskHealth disk;
  fault_t fault;
  EXPECT_FALSE(disk.Update(Disk(false, 0), 1, &fault));
  ASSERT_TRUE(disk.Update(Disk(true, 5), 2, &fault));
  EXPECT_EQ(fault.severity, fault_t::SEVERITY_ERROR);
  EXPECT_NE(fault.reason.find("No space left on device"), std::string::npos) << fault.reason;
  EXPECT_TRUE(disk.failing());
  EXPECT_FALSE(disk.Update(Disk(true, 50), 3, &fault)) << "one error per episode";
  ASSERT_TRUE(disk.Update(Disk(false, 80), 4, &fault));
  EXPECT_EQ(fault.severity, fault_t::SEVERITY_INFO);
  EXPECT_NE(fault.reason.find("75 events dropped"), std::string::npos) << fault.reason;
  EXPECT_FALSE(disk.failing());
  EXPECT_FALSE(disk.Update(Disk(false, 80), 5, &fault));
}

TEST(DiskHealth, ALagAfterAFullDiskCountsOnlyWhatTheEpisodeDidNotReport) {
  DiskHealth disk;
  fault_t fault;
  ASSERT_TRUE(disk.Update(Disk(true, 0), 1, &fault));
  ASSERT_TRUE(disk.Update(Disk(false, 30), 2, &fault));  // 30 dropped while full: reported here
  EXPECT_FALSE(disk.Update(Disk(false, 30), 3, &fault)) << "the episode's drops are no lag";
  ASSERT_TRUE(disk.Update(Disk(false, 37), 4, &fault));
  EXPECT_NE(fault.reason.find("7 events dropped: the disk cannot keep up"), std::string::npos) << fault.reason;
}

TEST(DiskHealth, ReportsADiskThatCannotKeepUpOnce) {
  DiskHealth disk;
  fault_t fault;
  ASSERT_TRUE(disk.Update(Disk(false, 12), 1, &fault));
  EXPECT_EQ(fault.severity, fault_t::SEVERITY_ERROR);
  EXPECT_NE(fault.reason.find("12 events dropped: the disk cannot keep up"), std::string::npos) << fault.reason;
  EXPECT_FALSE(disk.Update(Disk(false, 40), 2, &fault));
}

}  // namespace
}  // namespace edsp
