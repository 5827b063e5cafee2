// edsp::Bus in one process: LCM over memq://, shared memory, both with a
// decimated mirror, bad packets, handler exceptions, seq gaps, set-up errors.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <limits>
#include <thread>

#include <gtest/gtest.h>

#include "thrown_message.h"

#include "edsp/config_file/config_error.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/leg_command_t.hpp"
#include "edsp/transport/bus.h"
#include "memq_bus.h"  // tests/support
#include "edsp/transport/seq_gap.h"
#include "scratch_dir.h"

namespace edsp {
namespace {

TransportConfig MemqConfig() { return test_support::MemqConfig("bustest"); }

TransportConfig Routed(const std::string& channel, ChannelPath path, std::uint32_t mirror_every = 1) {
  TransportConfig config = MemqConfig();
  ChannelRoute route;
  route.path = path;
  route.mirror_every = mirror_every;
  route.slots = 16;
  route.slot_size_bytes = 512;
  config.channels[channel] = route;
  return config;
}

pose_setpoint_t Setpoint(std::int64_t seq) {
  pose_setpoint_t msg{};
  msg.utime = 1000 + seq;
  msg.seq = seq;
  msg.session_id = 7;
  for (int k = 0; k < 6; ++k) msg.pose[k] = 0.1 * k + static_cast<double>(seq);
  msg.trajectory = "Lz";
  msg.segment = 2;
  return msg;
}

void ExpectSame(const pose_setpoint_t& a, const pose_setpoint_t& b) {
  EXPECT_EQ(a.seq, b.seq);
  EXPECT_EQ(a.session_id, b.session_id);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(a.pose[k], b.pose[k]);
  EXPECT_EQ(a.trajectory, b.trajectory);
}

int HandleAll(Bus& bus) {
  int total = 0;
  for (int k = 0; k < 50; ++k) total += bus.Handle(std::chrono::milliseconds(1));
  return total;
}

TEST(Bus, LcmPathDeliversTypedMessages) {
  Bus bus(MemqConfig());
  std::vector<pose_setpoint_t> got;
  bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [&](const pose_setpoint_t& m) { got.push_back(m); });
  for (int k = 1; k <= 3; ++k) EXPECT_TRUE(bus.Publish("EDSP_SETPOINT", Setpoint(k)));
  HandleAll(bus);
  ASSERT_EQ(got.size(), 3u);
  ExpectSame(got[2], Setpoint(3));
  EXPECT_EQ(bus.Counters("EDSP_SETPOINT").received, 3u);
  EXPECT_EQ(bus.Counters("EDSP_SETPOINT").published, 3u);
}

// Regression (fuzz_lcm_decode): a string with an embedded NUL. lcm-gen's
// encoder stops at the NUL while getEncodedSize() counts the whole string;
// the packet on the wire must be exactly what encode wrote.
TEST(Bus, APacketIsWhatEncodeWroteEvenWithANulInAString) {
  Bus bus(MemqConfig());
  std::vector<std::uint32_t> sizes;
  std::vector<int> consumed;
  bus.lcm().Subscribe("EDSP_SETPOINT", [&](const std::string&, const std::uint8_t* data, std::uint32_t size) {
    sizes.push_back(size);
    pose_setpoint_t m;
    consumed.push_back(m.decode(data, 0, static_cast<int>(size)));
  });
  pose_setpoint_t msg = Setpoint(1);
  msg.trajectory = std::string("Lz\0after the NUL", 17);
  ASSERT_TRUE(bus.Publish("EDSP_SETPOINT", msg));
  HandleAll(bus);
  ASSERT_EQ(sizes.size(), 1u);
  EXPECT_LT(sizes[0], static_cast<std::uint32_t>(msg.getEncodedSize()));
  EXPECT_EQ(consumed[0], static_cast<int>(sizes[0]));  // every byte sent is the message
}

// Regression (fuzz_lcm_decode): a packet whose string length field is
// zero or negative made lcm-gen's decoder throw std::length_error (or, for
// INT32_MIN, overflow and read past the packet), which came out of
// Handle and stopped the node. It is a bad packet, counted and dropped.
TEST(Bus, APacketWithAnAbsurdStringLengthIsDroppedNotThrown) {
  Bus bus(MemqConfig());
  int delivered = 0;
  bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [&](const pose_setpoint_t&) { ++delivered; });
  const pose_setpoint_t msg = Setpoint(1);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  // fingerprint, utime, seq, session_id, pose, velocity, acceleration: then
  // the trajectory's big-endian length.
  const std::size_t at = 8 + 8 + 8 + 8 + 3 * 6 * 8;
  for (const std::uint32_t length : {0xFFFFFFF0u, 0u, 0x80000000u}) {
    for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<std::uint8_t>(length >> (24 - 8 * k));
    bus.lcm().Publish("EDSP_SETPOINT", bytes.data(), static_cast<std::uint32_t>(bytes.size()));
    EXPECT_NO_THROW(HandleAll(bus));
  }
  EXPECT_EQ(delivered, 0);
  EXPECT_EQ(bus.Counters("EDSP_SETPOINT").decode_errors, 3u);
}

TEST(Bus, ForeignAndTruncatedPacketsAreCountedNeverDelivered) {
  Bus bus(MemqConfig());
  int delivered = 0;
  bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [&](const pose_setpoint_t&) { ++delivered; });
  // A leg command on the setpoint channel (foreign fingerprint) ...
  leg_command_t foreign{};
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(foreign.getEncodedSize()));
  foreign.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  bus.lcm().Publish("EDSP_SETPOINT", bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  // ... a setpoint cut in half, and noise.
  const pose_setpoint_t whole = Setpoint(1);
  bytes.resize(static_cast<std::size_t>(whole.getEncodedSize()));
  whole.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  bus.lcm().Publish("EDSP_SETPOINT", bytes.data(), static_cast<std::uint32_t>(bytes.size() / 2));
  const std::uint8_t noise[3] = {1, 2, 3};
  bus.lcm().Publish("EDSP_SETPOINT", noise, 3);
  HandleAll(bus);
  EXPECT_EQ(delivered, 0);
  const ChannelCounters& c = bus.Counters("EDSP_SETPOINT");
  EXPECT_EQ(c.decode_errors, 3u);
  EXPECT_NE(c.last_error.find("EDSP_SETPOINT"), std::string::npos) << c.last_error;
}

TEST(Bus, HandlerExceptionIsRethrownFromHandleAndTheBusCarriesOn) {
  Bus bus(MemqConfig());
  int calls = 0;
  bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [&](const pose_setpoint_t& m) {
    ++calls;
    if (m.seq == 1) throw std::runtime_error("bad setpoint 1");
  });
  bus.Publish("EDSP_SETPOINT", Setpoint(1));
  EXPECT_THROW(
      {
        for (int k = 0; k < 50; ++k) bus.Handle(std::chrono::milliseconds(1));
      },
      std::runtime_error);
  bus.Publish("EDSP_SETPOINT", Setpoint(2));
  HandleAll(bus);
  EXPECT_EQ(calls, 2);
}

TEST(Bus, SeqGapsAreCounted) {
  Bus bus(MemqConfig());
  bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [](const pose_setpoint_t&) {});
  for (std::int64_t seq : {1, 2, 5, 6, 10}) bus.Publish("EDSP_SETPOINT", Setpoint(seq));
  HandleAll(bus);
  EXPECT_EQ(bus.Counters("EDSP_SETPOINT").seq_gaps, 2u + 3u);
}

TEST(Bus, SeqGapsAreCountedPerSessionWhenTwoGroupsShareAChannel) {
  Bus bus(MemqConfig());
  bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [](const pose_setpoint_t&) {});
  for (std::int64_t k = 1; k <= 5; ++k) {
    bus.Publish("EDSP_SETPOINT", Setpoint(k));  // session 7
    pose_setpoint_t other = Setpoint(1000 + k);
    other.session_id = 99;
    if (k != 3) bus.Publish("EDSP_SETPOINT", other);  // session 99 loses one
  }
  HandleAll(bus);
  EXPECT_EQ(bus.Counters("EDSP_SETPOINT").seq_gaps, 1u);
}

TEST(Bus, ShmPathDeliversTypedMessages) {
  Bus bus(Routed("EDSP_SETPOINT", ChannelPath::kShm));
  auto publisher = bus.Advertise<pose_setpoint_t>("EDSP_SETPOINT");
  std::vector<pose_setpoint_t> got;
  bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [&](const pose_setpoint_t& m) { got.push_back(m); });
  for (int k = 1; k <= 5; ++k) EXPECT_TRUE(publisher.Publish(Setpoint(k)));
  EXPECT_EQ(bus.Handle(std::chrono::milliseconds(10)), 5);
  ASSERT_EQ(got.size(), 5u);
  ExpectSame(got[4], Setpoint(5));
  EXPECT_EQ(publisher.counters().published, 5u);
}

TEST(Bus, BothPathMirrorsEveryNthMessageOnLcm) {
  Bus bus(Routed("TEST_MIRRORED", ChannelPath::kBoth, 3));
  auto publisher = bus.Advertise<pose_setpoint_t>("TEST_MIRRORED");
  std::vector<std::int64_t> shm_seqs, lcm_seqs;
  bus.Subscribe<pose_setpoint_t>("TEST_MIRRORED", [&](const pose_setpoint_t& m) { shm_seqs.push_back(m.seq); });
  bus.lcm().Subscribe("TEST_MIRRORED", [&](const std::string&, const std::uint8_t* data, std::uint32_t size) {
    pose_setpoint_t m;
    ASSERT_GE(m.decode(data, 0, static_cast<int>(size)), 0);
    lcm_seqs.push_back(m.seq);
  });
  for (int k = 1; k <= 9; ++k) publisher.Publish(Setpoint(k));
  HandleAll(bus);
  EXPECT_EQ(shm_seqs, (std::vector<std::int64_t>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(lcm_seqs, (std::vector<std::int64_t>{3, 6, 9}));
  EXPECT_EQ(publisher.counters().mirrored, 3u);
}

TEST(Bus, MessageTooBigForItsSlotIsRefusedAndCounted) {
  Bus bus(Routed("EDSP_SETPOINT", ChannelPath::kShm));
  pose_setpoint_t big = Setpoint(1);
  big.trajectory.assign(1000, 'x');  // slot is 512 bytes
  EXPECT_FALSE(bus.Publish("EDSP_SETPOINT", big));
  EXPECT_EQ(bus.Counters("EDSP_SETPOINT").publish_failures, 1u);
}

TEST(Bus, SecondWriterOfAChannelIsRefusedNamingIt) {
  const TransportConfig config = Routed("EDSP_SETPOINT", ChannelPath::kShm);
  Bus first(config), second(config);
  first.Advertise<pose_setpoint_t>("EDSP_SETPOINT");
  try {
    second.Advertise<pose_setpoint_t>("EDSP_SETPOINT");
    FAIL() << "no error";
  } catch (const TransportError& e) {
    EXPECT_NE(std::string(e.what()).find("EDSP_SETPOINT"), std::string::npos) << e.what();
  }
}

// The channel table fixes each EDSP_* channel's type: a node that would
// publish or subscribe another is refused at set-up, naming both.
TEST(Bus, AnEdspChannelTakesOnlyItsTablesType) {
  Bus bus(Routed("EDSP_SETPOINT", ChannelPath::kLcm));
  try {
    bus.Advertise<leg_command_t>("EDSP_SETPOINT");
    FAIL() << "no error";
  } catch (const TransportError& e) {
    EXPECT_STREQ(e.what(), "EDSP_SETPOINT carries pose_setpoint_t (channels.h), not leg_command_t");
  }
  EXPECT_THROW(bus.Subscribe<leg_command_t>("EDSP_SETPOINT", [](const leg_command_t&) {}), TransportError);
  EXPECT_NO_THROW(bus.Advertise<pose_setpoint_t>("EDSP_SETPOINT"));
  EXPECT_NO_THROW(bus.Advertise<leg_command_t>("MY_APP_COMMANDS")) << "other channels are the user's";
}

TEST(Bus, BadLcmUrlIsNamed) {
  TransportConfig config;
  config.lcm_url = "carrier-pigeon://loft";
  try {
    Bus bus(config);
    FAIL() << "no error";
  } catch (const TransportError& e) {
    EXPECT_NE(std::string(e.what()).find("carrier-pigeon://loft"), std::string::npos);
  }
}

TEST(Bus, FileUrlRecordsAndReplaysALog) {
  const std::string log = test_support::ScratchRoot() + "/bus_test.lcmlog";
  {
    TransportConfig write;
    write.lcm_url = "file://" + log + "?mode=w";
    Bus recorder(write);
    for (int k = 1; k <= 4; ++k) ASSERT_TRUE(recorder.Publish("EDSP_SETPOINT", Setpoint(k)));
  }
  TransportConfig read;
  read.lcm_url = "file://" + log + "?speed=0";  // as fast as possible
  Bus replay(read);
  std::vector<std::int64_t> seqs;
  replay.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [&](const pose_setpoint_t& m) { seqs.push_back(m.seq); });
  HandleAll(replay);
  EXPECT_EQ(seqs, (std::vector<std::int64_t>{1, 2, 3, 4}));
  ::unlink(log.c_str());
}

TEST(TransportConfig, ParsesRoutesAndDefaults) {
  const TransportConfig c = ParseTransportConfig(R"(
[transport]
lcm_url = "udpm://239.255.76.67:7667?ttl=1"
shm_prefix = "rig1"
shm_permissions = "0660"
[transport.channels.EDSP_LEG_COMMAND]
path = "both"
mirror_every = 10
slots = 128
slot_size_bytes = 1024
[transport.channels.EDSP_LEG_STATE]
path = "shm"
)",
                                                 "group.toml", {});
  EXPECT_EQ(c.lcm_url, "udpm://239.255.76.67:7667?ttl=1");
  EXPECT_EQ(c.shm_permissions, 0660u);
  EXPECT_EQ(c.SegmentName("EDSP_LEG_STATE"), "rig1.EDSP_LEG_STATE");
  EXPECT_EQ(c.Route("EDSP_LEG_COMMAND").path, ChannelPath::kBoth);
  EXPECT_EQ(c.Route("EDSP_LEG_COMMAND").mirror_every, 10u);
  EXPECT_EQ(c.Route("EDSP_LEG_COMMAND").slots, 128u);
  EXPECT_EQ(c.Route("EDSP_LEG_STATE").path, ChannelPath::kShm);
  EXPECT_EQ(c.Route("EDSP_TRACKER").path, ChannelPath::kLcm);
  EXPECT_EQ(ParseTransportConfig("", "empty.toml", {}).lcm_url, kDefaultLcmUrl);
}

std::string ConfigErrorOf(const std::string& text) {
  return test_support::ThrownMessage<ConfigError>([&] { ParseTransportConfig(text, "group.toml", {}); });
}

TEST(TransportConfig, ErrorsNameFileLineAndKey) {
  const std::string head = "[transport.channels.EDSP_X]\n";
  EXPECT_NE(ConfigErrorOf(head + "path = \"udp\"\n").find("group.toml:2: [transport.channels.EDSP_X] path = \"udp\""),
            std::string::npos);
  EXPECT_NE(ConfigErrorOf(head + "slots = 100\n").find("power of two"), std::string::npos);
  EXPECT_NE(ConfigErrorOf(head + "mirror_every = 0\n").find("mirror_every"), std::string::npos);
  EXPECT_NE(ConfigErrorOf(head + "slot = 8\n").find("unknown key"), std::string::npos);
  EXPECT_NE(ConfigErrorOf("[transport]\nshm_permissions = \"0044\"\n").find("shm_permissions"), std::string::npos);
  EXPECT_NE(ConfigErrorOf("[transport]\nurl = \"x\"\n").find("unknown key [transport] url"), std::string::npos);
  EXPECT_NE(ConfigErrorOf("[transport\n").find("group.toml:1:"), std::string::npos);
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

// A node with two shm inputs and an LCM one (the kinematics node in a shm
// group): a message on the second shm channel wakes Handle at once, not at
// its timeout, and an LCM message still gets through.
TEST(Bus, MixedInputsWakeOnAnyShmChannelAndStillServeLcm) {
  TransportConfig config = Routed("EDSP_SETPOINT", ChannelPath::kShm);
  config.channels["TEST_STATES"] = config.channels["EDSP_SETPOINT"];
  Bus writer_bus(config);
  auto setpoints = writer_bus.Advertise<pose_setpoint_t>("EDSP_SETPOINT");
  auto states = writer_bus.Advertise<pose_setpoint_t>("TEST_STATES");
  Bus bus(config);
  std::vector<std::string> got;
  for (const char* channel : {"EDSP_SETPOINT", "TEST_STATES", "TEST_REQUESTS"}) {
    bus.Subscribe<pose_setpoint_t>(channel, [&got, channel](const pose_setpoint_t&) { got.push_back(channel); });
  }
  for (int k = 0; k < 3; ++k) bus.Handle(std::chrono::milliseconds(5));  // attach
  std::thread publisher([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    states.Publish(Setpoint(1));
  });
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(bus.Handle(std::chrono::seconds(3)), 1);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  publisher.join();
  EXPECT_EQ(got, std::vector<std::string>{"TEST_STATES"});
  // memq:// delivers to the publishing instance only: publish on `bus` itself.
  bus.Publish("TEST_REQUESTS", Setpoint(2));
  EXPECT_EQ(bus.Handle(std::chrono::milliseconds(100)), 1);
  EXPECT_EQ(got.back(), "TEST_REQUESTS");
  (void)setpoints;
}

TEST(Bus, MixedInputsWakeOnLcmAtOnceNotAtTheNextSlice) {
  // A node with shm and LCM inputs sleeps on both: an LCM message wakes it
  // (through the socket's FdDoorbell), not the 1 s safety slice.
  TransportConfig config = Routed("TEST_STATES", ChannelPath::kShm);
  Bus writer_bus(config);
  auto states = writer_bus.Advertise<pose_setpoint_t>("TEST_STATES");
  Bus bus(config);
  int lcm_messages = 0;
  bus.Subscribe<pose_setpoint_t>("TEST_STATES", [](const pose_setpoint_t&) {});
  bus.Subscribe<pose_setpoint_t>("TEST_REQUESTS", [&](const pose_setpoint_t&) { ++lcm_messages; });
  for (int k = 0; k < 3; ++k) bus.Handle(std::chrono::milliseconds(5));  // attach
  const pose_setpoint_t msg = Setpoint(3);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  // Timed from the publish, not from the call: a thread started late on a
  // busy machine delays the message, not the wake. Waiting for the 1 s slice
  // would take the rest of it (950 ms after a publish at 50 ms);
  // half of it is the bound, so only a stall of half a second could fail a
  // correct wake.
  constexpr auto kHalfSlice = std::chrono::milliseconds(500);
  for (int round = 0; round < 3; ++round) {  // the doorbell re-arms after each drain
    std::atomic<std::chrono::steady_clock::rep> published_at{0};
    std::thread publisher([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      published_at = std::chrono::steady_clock::now().time_since_epoch().count();
      bus.lcm().Publish("TEST_REQUESTS", bytes.data(),
                        static_cast<std::uint32_t>(bytes.size()));  // LCM publish is thread-safe
    });
    EXPECT_EQ(bus.Handle(std::chrono::seconds(5)), 1) << round;
    const auto woke = std::chrono::steady_clock::now();
    publisher.join();
    const std::chrono::steady_clock::time_point sent{std::chrono::steady_clock::duration(published_at.load())};
    EXPECT_LT(woke - sent, kHalfSlice) << "round " << round << ": woke "
                                       << std::chrono::duration_cast<std::chrono::milliseconds>(woke - sent).count()
                                       << " ms after the publish";
  }
  EXPECT_EQ(lcm_messages, 3);
  (void)states;
}

// Regression (the flood under UBSan): foreign packets carry any seq; the
// logger's gap count overflowed int64 on them and stopped the logger.
TEST(SeqGap, CountsLossNeverOverflowsAndIgnoresForeignNumbers) {
  EXPECT_EQ(SeqGap(-1, 5), 0);  // first message
  EXPECT_EQ(SeqGap(5, 6), 0);
  EXPECT_EQ(SeqGap(5, 9), 3);
  EXPECT_EQ(SeqGap(9, 2), 0);  // a restarted publisher
  EXPECT_EQ(SeqGap(7736393874816021169, std::numeric_limits<std::int64_t>::max()), 0);
  EXPECT_EQ(SeqGap(0, std::numeric_limits<std::int64_t>::max()), 0);  // foreign, not 9e18 lost
  EXPECT_EQ(SeqGap(std::numeric_limits<std::int64_t>::max(), 0), 0);
  EXPECT_EQ(SeqGap(0, kImplausibleSeqGap), kImplausibleSeqGap - 1);
}

}  // namespace
}  // namespace edsp
