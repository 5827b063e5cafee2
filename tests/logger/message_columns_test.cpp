// Messages as columns (the Python package's numpy arrays): every field in
// the .lcm order with its shape and exact value, matrices row-major, text
// kept; a channel keeps its first type and counts the rest; foreign packets
// are counted by channel; an empty table of a type has the decoded one's
// columns; a log is read up to its damage. And a live recording from the
// Bus: every message of a shared-memory ring, the bound on memory, the
// recording saved as a log that reads back the same.
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/arm_t.hpp"
#include "edsp/arm_v1_t.hpp"
#include "edsp/calibration_v1_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/logger/bus_recording.h"
#include "edsp/logger/message_columns.h"
#include "edsp/motion_reply_v1_t.hpp"
#include "edsp/motion_status_v1_t.hpp"
#include "edsp/platform_config_t.hpp"
#include "edsp/pr_mode_v1_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "log_builder.h"  // tests/support
#include "encoded.h"      // tests/support
#include "memq_bus.h"     // tests/support

namespace edsp {
namespace {

template <typename Msg>
std::vector<std::uint8_t> Encode(const Msg& msg) {
  return test_support::Encoded(msg);
}

leg_state_t LegState(std::int64_t seq) {
  leg_state_t m{};
  m.utime = 1000 + seq, m.seq = seq, m.command_seq = seq - 1;
  for (int i = 0; i < 6; ++i) {
    m.motor_angle_rad[i] = 0.1 * i + static_cast<double>(seq), m.encoder_length_m[i] = 1.5 + 1e-6 * i;
    m.drive_status[i] = static_cast<std::int8_t>(i % 3);
  }
  return m;
}

std::size_t Index(const ChannelColumns& table, const std::string& name) {
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    if (table.columns[i].name == name) return i;
  }
  throw std::runtime_error("no column " + name);
}

const Column& Named(const ChannelColumns& table, const std::string& name) { return table.columns[Index(table, name)]; }

std::vector<std::int64_t> ReceiveStamps(const ChannelColumns& t) {
  std::vector<std::int64_t> out;
  for (std::int64_t row = 0; row < t.rows(); ++row) out.push_back(t.Value<std::int64_t>(row, 0));
  return out;
}

TEST(MessageColumns, EveryFieldInOrderWithItsShapeAndValue) {
  MessageColumns columns;
  for (std::int64_t seq = 0; seq < 3; ++seq) {
    const auto bytes = Encode(LegState(seq));
    columns.Add("EDSP_LEG_STATE", bytes.data(), bytes.size(), 500 + seq);
  }
  const ChannelColumns& t = columns.channels().at("EDSP_LEG_STATE");
  EXPECT_EQ(t.type, "edsp.leg_state_t");
  EXPECT_EQ(ReceiveStamps(t), (std::vector<std::int64_t>{500, 501, 502}));
  std::vector<std::string> names;
  for (const Column& c : t.columns) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"receive_utime", "utime", "seq", "command_seq", "motor_angle_rad",
                                             "motor_velocity_rad_s", "encoder_length_m", "drive_status"}));
  const Column& angles = Named(t, "motor_angle_rad");
  EXPECT_EQ(angles.kind, ColumnKind::kDouble);
  EXPECT_EQ(angles.shape, std::vector<std::size_t>{6});
  EXPECT_EQ(angles.bytes, 6 * sizeof(double));
  EXPECT_EQ(t.Value<double>(2, Index(t, "motor_angle_rad"), 4), 0.1 * 4 + 2.0);
  const Column& status = Named(t, "drive_status");
  EXPECT_EQ(status.kind, ColumnKind::kInt8);
  EXPECT_EQ(t.Value<std::int8_t>(1, Index(t, "drive_status"), 5), 2);
  EXPECT_EQ(t.Value<std::int64_t>(2, Index(t, "command_seq")), 1);
  // Each field at its natural alignment, the row a multiple of 8 (numpy's aligned struct).
  for (const Column& c : t.columns) EXPECT_EQ(c.offset % (c.kind == ColumnKind::kInt8 ? 1 : 8), 0u) << c.name;
  EXPECT_EQ(t.row_bytes % 8, 0u);
  EXPECT_GE(t.row_bytes, status.offset + status.bytes);
}

TEST(MessageColumns, MatricesAreRowMajorAndTextIsKept) {
  platform_config_t config{};
  config.preset = "huang2021";
  config.config_toml = "[geometry]\nbase_radius_m = 1.0\n";
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < 3; ++k) config.base_joints_m[i][k] = 10 * i + k;
  }
  MessageColumns columns;
  const auto bytes = Encode(config);
  columns.Add("EDSP_CONFIG", bytes.data(), bytes.size(), 1);
  const ChannelColumns& t = columns.channels().at("EDSP_CONFIG");
  const Column& joints = Named(t, "base_joints_m");
  EXPECT_EQ(joints.shape, (std::vector<std::size_t>{6, 3}));
  EXPECT_EQ(t.Value<double>(0, Index(t, "base_joints_m"), 4 * 3 + 2), 42.0);
  EXPECT_EQ(Named(t, "config_toml").text, std::vector<std::string>{config.config_toml});
  EXPECT_EQ(Named(t, "preset").kind, ColumnKind::kText);
}

// A log recorded before requests carried a request_id and replies a code
// holds the older layouts: their fingerprints are what lcm-gen gave those
// layouts (an independent truth: generated from the .lcm files as they
// were), and such a log reads with the fields it has.
TEST(MessageColumns, ALogOfTheOlderRequestLayoutsReadsWithTheirFields) {
  EXPECT_EQ(static_cast<std::uint64_t>(arm_v1_t::getHash()), 0xd1a6f4727f28a861ULL);
  EXPECT_EQ(static_cast<std::uint64_t>(pr_mode_v1_t::getHash()), 0xb10443baebef808eULL);
  EXPECT_EQ(static_cast<std::uint64_t>(calibration_v1_t::getHash()), 0x6c966427a672532fULL);
  EXPECT_EQ(static_cast<std::uint64_t>(motion_reply_v1_t::getHash()), 0x0174a79cff17ce1dULL);
  EXPECT_EQ(static_cast<std::uint64_t>(motion_status_v1_t::getHash()), 0x3262226a3b339d61ULL);
  EXPECT_NE(arm_v1_t::getHash(), arm_t::getHash());  // the layout did change
  EXPECT_NE(motion_status_v1_t::getHash(), motion_status_t::getHash());
  MessageColumns columns;
  arm_v1_t arm{};
  arm.utime = 7, arm.seq = 1, arm.session_id = 9, arm.operator_name = "alice";
  const auto old_arm = Encode(arm);
  columns.Add("EDSP_ARM", old_arm.data(), old_arm.size(), 11);
  motion_reply_v1_t reply{};
  reply.request_id = 5, reply.accepted = 1, reply.reason = "moves";
  const auto old_reply = Encode(reply);
  columns.Add("EDSP_MOTION_REPLY", old_reply.data(), old_reply.size(), 12);
  const ChannelColumns& a = columns.channels().at("EDSP_ARM");
  EXPECT_EQ(a.type, "edsp.arm_v1_t");
  EXPECT_EQ(Named(a, "operator_name").text, std::vector<std::string>{"alice"});
  EXPECT_EQ(a.Value<std::int64_t>(0, Index(a, "session_id")), 9);
  const ChannelColumns& r = columns.channels().at("EDSP_MOTION_REPLY");
  EXPECT_EQ(r.type, "edsp.motion_reply_v1_t");
  EXPECT_EQ(r.Value<std::int64_t>(0, Index(r, "request_id")), 5);
  for (const Column& c : r.columns) EXPECT_NE(c.name, "code");
  motion_status_v1_t status{};
  status.frame = "fixture";
  const auto old_status = Encode(status);
  columns.Add("EDSP_MOTION_STATUS", old_status.data(), old_status.size(), 13);
  const ChannelColumns& st = columns.channels().at("EDSP_MOTION_STATUS");
  EXPECT_EQ(st.type, "edsp.motion_status_v1_t");
  EXPECT_EQ(Named(st, "frame").text, std::vector<std::string>{"fixture"});
  for (const Column& c : st.columns) EXPECT_EQ(c.name.rfind("frame_pose", 0), std::string::npos) << c.name;
}

TEST(MessageColumns, AChannelKeepsItsFirstTypeAndForeignPacketsAreCounted) {
  MessageColumns columns;
  const auto state = Encode(LegState(1));
  tracker_point_t point{};
  const auto other = Encode(point);
  const std::vector<std::uint8_t> foreign(40, 0x5a);
  columns.Add("EDSP_LEG_STATE", foreign.data(), foreign.size(), 1);  // before the first decodable one
  columns.Add("EDSP_LEG_STATE", state.data(), state.size(), 2);
  columns.Add("EDSP_LEG_STATE", other.data(), other.size(), 3);
  columns.Add("EDSP_LEG_STATE", state.data(), 20, 4);  // truncated
  columns.Add("OTHER", foreign.data(), foreign.size(), 5);
  const ChannelColumns& t = columns.channels().at("EDSP_LEG_STATE");
  EXPECT_EQ(t.rows(), 1);
  EXPECT_EQ(t.skipped, 3);
  EXPECT_EQ(columns.unknown(), (std::map<std::string, std::int64_t, std::less<>>{{"OTHER", 1}}));
  EXPECT_EQ(columns.channels().count("OTHER"), 0u);
}

TEST(MessageColumns, AnEmptyTableHasTheColumnsOfADecodedOne) {
  MessageColumns columns;
  const auto bytes = Encode(LegState(1));
  columns.Add("EDSP_LEG_STATE", bytes.data(), bytes.size(), 1);
  const ChannelColumns decoded = columns.channels().at("EDSP_LEG_STATE");
  for (const char* name : {"leg_state_t", "edsp.leg_state_t"}) {
    const ChannelColumns empty = EmptyColumns(name);
    EXPECT_EQ(empty.type, "edsp.leg_state_t");
    EXPECT_EQ(empty.rows(), 0);
    EXPECT_EQ(empty.row_bytes, decoded.row_bytes);
    ASSERT_EQ(empty.columns.size(), decoded.columns.size());
    for (std::size_t i = 0; i < empty.columns.size(); ++i) {
      EXPECT_EQ(empty.columns[i].name, decoded.columns[i].name);
      EXPECT_EQ(empty.columns[i].shape, decoded.columns[i].shape);
      EXPECT_EQ(empty.columns[i].offset, decoded.columns[i].offset);
    }
  }
  EXPECT_THROW(EmptyColumns("no_such_t"), std::invalid_argument);
}

TEST(MessageColumns, ALogIsReadUpToItsDamageAndFiltered) {
  const std::string path = testing::TempDir() + "/columns_" + std::to_string(::getpid()) + ".lcmlog";
  {
    test_support::LogBuilder log(path);
    for (std::int64_t seq = 0; seq < 4; ++seq) log.Add("EDSP_LEG_STATE", LegState(seq));
    log.Add("EDSP_TRACKER", tracker_point_t{});
  }
  {
    std::ofstream tail(path, std::ios::app | std::ios::binary);
    tail << "\xED\xA1\xDA\x01torn";
  }
  const LogColumns all = ReadLogColumns(path, [](const std::string&) { return true; });
  EXPECT_EQ(all.messages.channels().at("EDSP_LEG_STATE").rows(), 4);
  EXPECT_EQ(all.messages.channels().at("EDSP_TRACKER").rows(), 1);
  EXPECT_TRUE(all.damaged);
  const LogColumns some = ReadLogColumns(path, [](const std::string& c) { return c == "EDSP_TRACKER"; });
  EXPECT_EQ(some.messages.channels().size(), 1u);
  std::filesystem::remove(path);
  EXPECT_THROW(ReadLogColumns(path, [](const std::string&) { return true; }), std::runtime_error);
}

// The recorder reads a shared-memory channel from its ring, as the group
// routes it: every message another process's Bus wrote after it started.
TEST(BusRecording, RecordsEveryMessageOfARingAndSavesThemAsALog) {
  TransportConfig config = test_support::MemqConfig("bus_recording");
  config.channels["EDSP_LEG_STATE"].path = ChannelPath::kShm;
  BusRecording recording(config, "EDSP_LEG_STATE", 1 << 20);
  {
    Bus writer(config);  // another process's Bus: the same ring
    auto states = writer.Advertise<leg_state_t>("EDSP_LEG_STATE");
    for (std::int64_t seq = 1; seq <= 50; ++seq) ASSERT_TRUE(states.Publish(LegState(seq)));
    for (int wait = 0; wait < 200 && recording.stats().messages < 50; ++wait) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  recording.Stop();
  const BusRecordingStats stats = recording.stats();
  EXPECT_EQ(stats.messages, 50);
  EXPECT_EQ(stats.dropped, 0);
  EXPECT_EQ(stats.error, "");
  const MessageColumns columns = recording.Columns();
  const ChannelColumns& t = columns.channels().at("EDSP_LEG_STATE");
  ASSERT_EQ(t.rows(), 50);
  EXPECT_EQ(t.Value<std::int64_t>(0, Index(t, "seq")), 1);
  EXPECT_EQ(t.Value<std::int64_t>(49, Index(t, "seq")), 50);

  const std::string path = testing::TempDir() + "/recording_" + std::to_string(::getpid()) + ".lcmlog";
  recording.Save(path);
  recording.Save(path);  // replaced, not appended
  const LogColumns back = ReadLogColumns(path, [](const std::string&) { return true; });
  const ChannelColumns& read = back.messages.channels().at("EDSP_LEG_STATE");
  EXPECT_EQ(read.rows_data, t.rows_data);
  EXPECT_FALSE(back.damaged);
  std::filesystem::remove(path);
  EXPECT_THROW(recording.Save("/no/such/dir/x.lcmlog"), std::runtime_error);
}

TEST(BusRecording, KeepsWhatFitsAndCountsTheRest) {
  TransportConfig config = test_support::MemqConfig("bus_recording_bound");
  config.channels["EDSP_LEG_STATE"].path = ChannelPath::kShm;
  const std::int64_t one = static_cast<std::int64_t>(Encode(LegState(1)).size());
  BusRecording recording(config, "EDSP_LEG_STATE", 10 * one);
  Bus writer(config);
  auto states = writer.Advertise<leg_state_t>("EDSP_LEG_STATE");
  for (std::int64_t seq = 1; seq <= 25; ++seq) ASSERT_TRUE(states.Publish(LegState(seq)));
  for (int wait = 0; wait < 200 && recording.stats().messages + recording.stats().dropped < 25; ++wait) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  recording.Stop();
  EXPECT_EQ(recording.stats().messages, 10);
  EXPECT_EQ(recording.stats().dropped, 15);
  EXPECT_EQ(recording.Columns().channels().at("EDSP_LEG_STATE").rows(), 10);
}

TEST(BusRecording, ABadPatternIsNamed) {
  try {
    BusRecording recording(test_support::MemqConfig("bus_recording_bad"), "EDSP_(", 1 << 20);
    FAIL() << "a pattern that is no regex was taken";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("EDSP_("), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edsp
