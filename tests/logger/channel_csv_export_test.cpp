// edsp-log export --csv: one file per channel with every field, doubles
// exact through the text, text quoted (multi-line config TOML included),
// foreign and truncated packets counted and never written, a channel filter,
// a damaged log exported up to the damage, and errors naming what is wrong.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/channels.h"
#include "edsp/fault_t.hpp"
#include "edsp/leg_command_t.hpp"
#include "edsp/logger/channel_csv_export.h"
#include "edsp/message_types.h"
#include "edsp/platform_config_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "log_builder.h"  // tests/support
#include "scratch_dir.h"

namespace edsp {
namespace {

using test_support::LogBuilder;

// A minimal RFC 4180 reader, written independently of the exporter.
std::vector<std::vector<std::string>> ReadCsv(const std::string& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::vector<std::vector<std::string>> rows(1, std::vector<std::string>(1));
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"')
        rows.back().back() += '"', ++i;
      else if (c == '"')
        quoted = false;
      else
        rows.back().back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().emplace_back();
    } else if (c == '\n') {
      rows.emplace_back(1);
    } else {
      rows.back().back() += c;
    }
  }
  if (rows.back().size() == 1 && rows.back()[0].empty()) rows.pop_back();
  return rows;
}

std::size_t HeaderIndex(const std::vector<std::string>& header, const std::string& name) {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return i;
  }
  ADD_FAILURE() << "no column " << name;
  return 0;
}

class ChannelCsvExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::remove_all(dir_);
    LogBuilder b(log_);
    for (int k = 0; k < 3; ++k) {
      pose_setpoint_t s{};
      s.utime = 1000 + k;
      s.seq = k;
      s.session_id = 42;
      s.pose[2] = 1.511 + k / 3.0;
      s.pose[5] = -0.1 - 1e-17;
      s.trajectory = "Rz/move " + std::to_string(k);
      s.segment = k;
      b.Add("EDSP_SETPOINT", s);
    }
    leg_command_t c{};
    for (int i = 0; i < 6; ++i) c.command_length_m[i] = 1.9 + 1e-13 * i;
    c.pr_mode = leg_command_t::PR_SIGNED;
    b.Add("EDSP_LEG_COMMAND", c);
    b.AddBytes("EDSP_SETPOINT", {1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13,
                                 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25});  // foreign fingerprint
    std::vector<std::uint8_t> truncated(static_cast<std::size_t>(c.getEncodedSize()));
    c.encode(truncated.data(), 0, static_cast<int>(truncated.size()));
    truncated.resize(64);
    b.AddBytes("EDSP_LEG_COMMAND", truncated);                  // right type, cut short
    b.AddBytes("OTHER_APP", std::vector<std::uint8_t>(40, 7));  // nothing edsp knows
    platform_config_t cfg{};
    cfg.config_toml = "[geometry]\npreset = \"huang2021\"\n";
    cfg.base_joints_m[5][2] = 0.25;
    b.Add("EDSP_CONFIG", cfg);
    fault_t f{};
    f.reason = "setpoint x = nan, \"refused\"";
    b.Add("EDSP_FAULT", f);
  }
  void TearDown() override {
    std::filesystem::remove_all(dir_);
    std::filesystem::remove(log_);
  }
  const std::string stem_ = test_support::ScratchRoot() + "/csv_export";
  const std::string log_ = stem_ + ".lcmlog";
  const std::string dir_ = stem_ + "_csv";
};

TEST_F(ChannelCsvExportTest, EveryFieldOfEveryMessageOneFilePerChannel) {
  const ChannelCsvExport e = ExportChannelCsvs(log_, dir_);
  EXPECT_FALSE(e.damaged);
  ASSERT_EQ(e.channels.size(), 4u);
  EXPECT_EQ(e.channels.at("EDSP_SETPOINT").rows, 3);
  EXPECT_EQ(e.channels.at("EDSP_SETPOINT").skipped, 1);
  EXPECT_EQ(e.channels.at("EDSP_SETPOINT").type, "edsp.pose_setpoint_t");
  EXPECT_EQ(e.channels.at("EDSP_LEG_COMMAND").rows, 1);
  EXPECT_EQ(e.channels.at("EDSP_LEG_COMMAND").skipped, 1);
  EXPECT_EQ(e.unknown.at("OTHER_APP"), 1);
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/OTHER_APP.csv"));

  const auto sp = ReadCsv(dir_ + "/EDSP_SETPOINT.csv");
  ASSERT_EQ(sp.size(), 4u);
  const auto& h = sp[0];
  // log_time_s, utime, seq, session_id, pose×6, velocity×6, acceleration×6, trajectory, segment, phase
  EXPECT_EQ(h.size(), 1u + 3 + 18 + 3);
  for (std::size_t r = 1; r < sp.size(); ++r) EXPECT_EQ(sp[r].size(), h.size());
  EXPECT_EQ(h[0], "log_time_s");
  EXPECT_EQ(std::stod(sp[2][HeaderIndex(h, "log_time_s")]), 0.001);
  EXPECT_EQ(std::stoll(sp[3][HeaderIndex(h, "utime")]), 1002);
  EXPECT_EQ(std::stoll(sp[3][HeaderIndex(h, "session_id")]), 42);
  EXPECT_EQ(std::stod(sp[3][HeaderIndex(h, "pose_3")]), 1.511 + 2 / 3.0);
  EXPECT_EQ(std::stod(sp[3][HeaderIndex(h, "pose_6")]), -0.1 - 1e-17);
  EXPECT_EQ(sp[3][HeaderIndex(h, "trajectory")], "Rz/move 2");
  EXPECT_EQ(sp[3][HeaderIndex(h, "segment")], "2");
  EXPECT_EQ(h.back(), "phase");

  const auto lc = ReadCsv(dir_ + "/EDSP_LEG_COMMAND.csv");
  ASSERT_EQ(lc.size(), 2u);
  EXPECT_EQ(lc[1][HeaderIndex(lc[0], "pr_mode")], "2");
  EXPECT_EQ(std::stod(lc[1][HeaderIndex(lc[0], "command_length_m_6")]), 1.9 + 5e-13);

  const auto cfg = ReadCsv(dir_ + "/EDSP_CONFIG.csv");
  ASSERT_EQ(cfg.size(), 2u);
  EXPECT_EQ(cfg[1][HeaderIndex(cfg[0], "config_toml")], "[geometry]\npreset = \"huang2021\"\n");
  EXPECT_EQ(std::stod(cfg[1][HeaderIndex(cfg[0], "base_joints_m_6_3")]), 0.25);
  EXPECT_EQ(std::stod(cfg[1][HeaderIndex(cfg[0], "base_joints_m_1_1")]), 0.0);

  const auto faults = ReadCsv(dir_ + "/EDSP_FAULT.csv");
  ASSERT_EQ(faults.size(), 2u);
  EXPECT_EQ(faults[1][HeaderIndex(faults[0], "reason")], "setpoint x = nan, \"refused\"");
}

TEST_F(ChannelCsvExportTest, ChannelFilterAndDamage) {
  const auto size = std::filesystem::file_size(log_);
  std::filesystem::resize_file(log_, size - 10);  // the fault event cut short
  const ChannelCsvExport e = ExportChannelCsvs(log_, dir_, "EDSP_(SETPOINT|FAULT)");
  EXPECT_TRUE(e.damaged);
  EXPECT_GT(e.damage_offset, 0);
  ASSERT_EQ(e.channels.size(), 1u);
  EXPECT_EQ(e.channels.count("EDSP_SETPOINT"), 1u);
  EXPECT_TRUE(e.unknown.empty());
}

TEST_F(ChannelCsvExportTest, ErrorsNameWhatIsWrong) {
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { ExportChannelCsvs("/nonexistent/a.lcmlog", dir_); }).find("/nonexistent/a.lcmlog"),
            std::string::npos);
  EXPECT_NE(message([&] { ExportChannelCsvs(log_, dir_, "EDSP_(["); }).find("EDSP_(["), std::string::npos);
  EXPECT_NE(message([&] { ExportChannelCsvs(log_, "/proc/edsp_no/such"); }).find("/proc/edsp_no/such"),
            std::string::npos);
}

// Every channel of the table (channels.h) exports, with its own type: a
// channel or type added without what the export needs fails here.
TEST(ChannelCsvExport, EveryChannelOfTheTableExportsItsType) {
  const std::string stem = test_support::ScratchRoot() + "/csv_every";
  {
    LogBuilder b(stem + ".lcmlog");
    for (const channel::Channel& c : channel::kChannels) {
      bool written = false;
      ForEachMessageType([&](auto tag) {
        using Msg = typename decltype(tag)::type;
        if (written || c.type != Msg::getTypeName()) return;
        Msg msg{};
        msg.utime = 7;
        msg.seq = 3;
        b.Add(std::string(c.name), msg);
        written = true;
      });
      EXPECT_TRUE(written) << c.name << ": its type " << c.type << " is not in message_types.h";
    }
  }
  const ChannelCsvExport e = ExportChannelCsvs(stem + ".lcmlog", stem + "_csv");
  EXPECT_TRUE(e.unknown.empty());
  for (const channel::Channel& c : channel::kChannels) {
    const std::string name(c.name);
    ASSERT_EQ(e.channels.count(name), 1u) << name << " was not exported";
    EXPECT_EQ(e.channels.at(name).type, "edsp." + std::string(c.type));
    EXPECT_EQ(e.channels.at(name).rows, 1);
    const auto rows = ReadCsv(e.channels.at(name).path);
    ASSERT_EQ(rows.size(), 2u) << name;
    EXPECT_EQ(rows[1][HeaderIndex(rows[0], "utime")], "7") << name;
    EXPECT_EQ(rows[1][HeaderIndex(rows[0], "seq")], "3") << name;
  }
  std::filesystem::remove_all(stem + "_csv");
  std::filesystem::remove(stem + ".lcmlog");
}

}  // namespace
}  // namespace edsp
