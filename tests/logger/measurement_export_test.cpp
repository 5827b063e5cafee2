// The measurement export on a log written here: rows only for valid tracker
// samples after a command, the setpoint/command/encoders of its instant beside each,
// the run from the trajectory name, every double exact, and a damaged log
// exported up to its damage.
#include <unistd.h>

#include <cstdio>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "log_builder.h"  // tests/support
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/logger/log_summary.h"
#include "edsp/logger/measurement_export.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "scratch_dir.h"

namespace edsp {
namespace {

using test_support::LogBuilder;

tracker_point_t Point(std::int64_t utime, double x, bool valid = true) {
  tracker_point_t p{};
  p.utime = utime;
  p.point_m[0] = x;
  p.point_m[1] = 1.0 / 3.0;
  p.point_m[2] = 1.511;
  p.valid = valid;
  return p;
}

pose_setpoint_t Setpoint(const char* trajectory, double z, std::int64_t utime = 150) {
  pose_setpoint_t s{};
  s.utime = utime;
  s.pose[2] = z;
  s.pose[5] = 0.1 + 1e-17;
  s.trajectory = trajectory;
  return s;
}

std::vector<std::vector<std::string>> Rows(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    rows.emplace_back();
    std::string cell;
    std::istringstream cells(line);
    while (std::getline(cells, cell, ',')) rows.back().push_back(cell);
  }
  return rows;
}

const std::string kPath = test_support::ScratchRoot() + "/export_test.lcmlog";

void WriteLog() {
  LogBuilder b(kPath);
  b.Add("EDSP_TRACKER", Point(100, 9.0));  // before any command: skipped
  b.Add("EDSP_SETPOINT", Setpoint("Lz/move 1", 1.4));
  leg_command_t c{};
  c.setpoint_utime = 150;
  for (int i = 0; i < 6; ++i) {
    c.command_length_m[i] = 1.9 + 0.001 * i + 1e-13;
    c.pr_correction_m[i] = 1e-3;
    c.ik_length_m[i] = c.command_length_m[i] + c.pr_correction_m[i] + 5e-5 * i;  // a calibration's correction
  }
  b.Add("EDSP_LEG_COMMAND", c);
  leg_state_t s{};
  for (int i = 0; i < 6; ++i) s.encoder_length_m[i] = 1.8 + 0.002 * i;
  b.Add("EDSP_LEG_STATE", s);
  b.Add("EDSP_TRACKER", Point(200, 1.2 + 1e-12));
  b.Add("EDSP_TRACKER", Point(300, 5.0, false));                 // beam broken: skipped
  b.Add("EDSP_SETPOINT", Setpoint("Rz/dwell 2", 1.5, 1500000));  // no command answers it: the last one
  b.Add("EDSP_TRACKER", Point(1500200, 1.3));
}

TEST(MeasurementExport, OneRowPerValidTrackerSampleWithTheLatestCommands) {
  WriteLog();
  std::ostringstream csv;
  const MeasurementExport e = ExportMeasurementCsv(kPath, csv);
  EXPECT_EQ(e.rows, 2);
  EXPECT_EQ(e.skipped, 2);
  EXPECT_FALSE(e.damaged);
  const auto rows = Rows(csv.str());
  ASSERT_EQ(rows.size(), 3u);
  ASSERT_EQ(rows[0].size(), 30u);
  EXPECT_EQ(rows[0][0], "time_s");
  EXPECT_EQ(rows[0][8], "leg_cmd_1_m");
  EXPECT_EQ(rows[0][20], "leg_corr_1_m");
  EXPECT_EQ(rows[0][28], "point_z_m");
  EXPECT_EQ(rows[0][29], "timing_event");
  EXPECT_EQ(rows[1][29], "0");
  EXPECT_EQ(rows[1][1], "Lz");
  EXPECT_EQ(rows[2][1], "Rz");
  EXPECT_EQ(std::stod(rows[1][0]), 0.0);
  EXPECT_DOUBLE_EQ(std::stod(rows[2][0]), 1.5);
  // Every double survives the text exactly.
  EXPECT_EQ(std::stod(rows[1][4]), 1.4);
  EXPECT_EQ(std::stod(rows[1][7]), 0.1 + 1e-17);
  EXPECT_EQ(std::stod(rows[1][9]), 1.9 + 0.001 * 1 + 1e-13);
  EXPECT_EQ(std::stod(rows[1][15]), 1.8 + 0.002 * 1);
  EXPECT_EQ(std::stod(rows[1][26]), 1.2 + 1e-12);
  EXPECT_EQ(std::stod(rows[1][27]), 1.0 / 3.0);
  // The calibration's correction: IK − PR − command, as the kinematics took it off.
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(std::stod(rows[1][static_cast<std::size_t>(20 + i)]), 5e-5 * i, 1e-15) << i;
  EXPECT_EQ(std::stod(rows[2][4]), 1.5);
  ::unlink(kPath.c_str());
}

// The logger hears the processes interleaved: here the tracker sample
// arrives before the setpoint, command and encoders stamped at or before it. Each
// sample is paired by the stamps (the platform at t against what was
// commanded before t), not by what happened to arrive first.
TEST(MeasurementExport, SamplesArePairedByTheirStampsNotByArrival) {
  {
    LogBuilder b(kPath);
    auto command = [&](std::int64_t setpoint_utime, double length) {
      leg_command_t c{};
      c.setpoint_utime = setpoint_utime;
      for (double& l : c.command_length_m) l = length;
      b.Add("EDSP_LEG_COMMAND", c);
    };
    b.Add("EDSP_SETPOINT", Setpoint("A/move 1", 1.0, 1000));
    command(1000, 1.0);
    b.Add("EDSP_TRACKER", Point(1750, 0.4));
    b.Add("EDSP_TRACKER", Point(2000, 0.5));
    pose_setpoint_t moving = Setpoint("A/move 1", 1.5, 1500);
    moving.velocity[2] = 1000.0;  // m/s: 0.25 m in the 250 µs to the first sample
    b.Add("EDSP_SETPOINT", moving);
    command(1500, 1.5);
    b.Add("EDSP_SETPOINT", Setpoint("A/move 1", 2.0, 2000));  // for the sample's instant
    command(2000, 2.0);
    b.Add("EDSP_SETPOINT", Setpoint("A/move 1", 2.5, 2001));  // after it
    command(2001, 2.5);
    leg_state_t legs{};
    legs.utime = 1900;
    for (double& l : legs.encoder_length_m) l = 1.9;
    b.Add("EDSP_LEG_STATE", legs);
  }
  std::ostringstream csv;
  const MeasurementExport e = ExportMeasurementCsv(kPath, csv);
  ASSERT_EQ(e.rows, 2);
  const auto rows = Rows(csv.str());
  // At 1750, between the setpoints stamped 1500 and 2000: the pose along
  // the 1500 one's velocity, the legs between the two commands; no encoders yet.
  EXPECT_DOUBLE_EQ(std::stod(rows[1][4]), 1.75);
  EXPECT_DOUBLE_EQ(std::stod(rows[1][8]), 1.75);
  EXPECT_EQ(rows[1][14], "");
  EXPECT_EQ(std::stod(rows[2][4]), 2.0);   // pose_cmd_z: the setpoint stamped 2000
  EXPECT_EQ(std::stod(rows[2][8]), 2.0);   // leg_cmd_1: the command answering it
  EXPECT_EQ(std::stod(rows[2][14]), 1.9);  // leg_enc_1: stamped 1900
  ::unlink(kPath.c_str());
}

// Setpoints missing from the log (the planner skipped ticks, the logger lost
// them): a sample past the carry lies between the setpoints around it, not
// at the last one's pose (which showed as a spike of speed × gap); across a
// gap longer than a stopped stream's, the pose stays where it was.
TEST(MeasurementExport, ASampleInAGapOfSetpointsLiesBetweenTheSetpointsAroundIt) {
  {
    LogBuilder b(kPath);
    auto setpoint = [&](std::int64_t utime, double z) {
      pose_setpoint_t s = Setpoint("A/move 1", z, utime);
      s.velocity[2] = 100.0;  // m/s: would carry the pose 0.4 m in 4 ms
      b.Add("EDSP_SETPOINT", s);
      leg_command_t c{};
      c.setpoint_utime = utime;
      for (double& l : c.command_length_m) l = z;
      b.Add("EDSP_LEG_COMMAND", c);
    };
    setpoint(1'000'000, 1.0);
    b.Add("EDSP_TRACKER", Point(1'004'000, 0.1));  // 4 ms into a 10 ms gap
    setpoint(1'010'000, 2.0);
    b.Add("EDSP_TRACKER", Point(1'060'000, 0.2));  // 50 ms into a 100 ms gap: a stopped stream
    setpoint(1'110'000, 3.0);
  }
  std::ostringstream csv;
  const MeasurementExport e = ExportMeasurementCsv(kPath, csv);
  ASSERT_EQ(e.rows, 2);
  const auto rows = Rows(csv.str());
  EXPECT_NEAR(std::stod(rows[1][4]), 1.4, 1e-12);  // pose_cmd_z between 1.0 and 2.0
  EXPECT_NEAR(std::stod(rows[1][8]), 1.4, 1e-12);  // leg_cmd_1 between the commands
  EXPECT_EQ(std::stod(rows[2][4]), 2.0);           // held where the stream stopped
  EXPECT_EQ(std::stod(rows[2][8]), 2.0);
  ::unlink(kPath.c_str());
}

// Stalls of the real-time system, each seen one way only, a tracker sample
// every millisecond, the drives' commands all at 0 and their encoders off
// by the tracking error:
// - the commands stop for 6 ms from 50 ms on (command_seq; the bridge kept
//   its time and rides through up to 10 ms): no stall;
// - the rig emulator's cycles stop for 10 ms from 249 ms on (EDSP_RIG_TRUTH;
//   the readings go on, as the bridge stamps its own reads), and the drives
//   are 1 mm off until 480 ms: flagged to the longest catch-up, 100 ms +
//   10 ms per ms stalled after it;
// - the commands stop for 12 ms from 560 ms on, the drives 1 mm off until
//   600 ms: flagged until 20 ms after they are back;
// - a leg state from before arrives late at 600 ms (no stall);
// - one rig cycle comes 1.6 ms after the last at 650 ms (its physics lost
//   0.6 ms), the drives never off: flagged to 10 + 20 ms after it;
// - from 700 ms on the drives trail by 100 µm (a lag at speed), the
//   readings stop for 5 ms at 720 ms, after which they trail by 150 µm:
//   under twice what they did before, normal;
// - from 800 ms on the drives' readings stop for good (a stall still open
//   when the samples are written): everything from 2 ms before it.
// The edges pinned to the millisecond.
TEST(MeasurementExport, SamplesNearAStallOfTheRealTimeSystemAreFlaggedUntilTheDrivesRecover) {
  {
    LogBuilder b(kPath);
    b.Add("EDSP_SETPOINT", Setpoint("A/move 1", 1.0, 1000));
    leg_command_t c{};
    c.setpoint_utime = 1000;
    b.Add("EDSP_LEG_COMMAND", c);
    std::int64_t seq = 0;
    for (std::int64_t t = 1000; t <= 900'000; t += 1000) {
      const bool commands_stalled = (t > 50'000 && t < 56'000) || (t > 560'000 && t < 572'000);
      const bool rig_stalled = t > 249'000 && t < 259'000;
      const bool readings_stalled = t > 720'000 && t < 725'000;
      if (!rig_stalled) {
        rig_truth_t truth{};
        truth.utime = t == 650'000 ? t + 600 : t;
        b.Add("EDSP_RIG_TRUTH", truth);
      }
      if (t <= 800'000 && !readings_stalled) {
        leg_state_t s{};
        s.utime = t;
        s.command_seq = commands_stalled ? seq : ++seq;
        const bool off = (t >= 259'000 && t < 480'000) || (t >= 572'000 && t < 600'000);
        const double error = off ? 1e-3 : t >= 725'000 ? 150e-6 : t >= 700'000 ? 100e-6 : 0.0;
        for (double& l : s.encoder_length_m) l = error;
        b.Add("EDSP_LEG_STATE", s);
      }
      if (t == 600'000) {
        leg_state_t late{};
        late.utime = t - 10'000;
        late.command_seq = seq - 10;
        b.Add("EDSP_LEG_STATE", late);
      }
      b.Add("EDSP_TRACKER", Point(t, 0.1));
    }
  }
  std::ostringstream csv;
  const MeasurementExport e = ExportMeasurementCsv(kPath, csv);
  const auto rows = Rows(csv.str());
  ASSERT_EQ(e.rows, 900);
  std::int64_t flagged = 0;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const std::int64_t ms = static_cast<std::int64_t>(k);  // the k-th sample's stamp
    const bool near = (ms >= 247 && ms <= 259 + 100 + 100) || (ms >= 558 && ms <= 619) || (ms >= 647 && ms <= 680) ||
                      (ms >= 718 && ms <= 755) || ms >= 798;
    EXPECT_EQ(rows[k][29], near ? "1" : "0") << "sample at " << ms << " ms";
    flagged += near;
  }
  EXPECT_EQ(e.timing_events, flagged);
  EXPECT_EQ(flagged, (459 - 247 + 1) + (619 - 558 + 1) + (680 - 647 + 1) + (755 - 718 + 1) + (900 - 798 + 1));
  ::unlink(kPath.c_str());
}

TEST(MeasurementExport, DamagedLogIsExportedUpToTheDamageAndSaysWhere) {
  WriteLog();
  const long size = [] {
    FILE* f = std::fopen(kPath.c_str(), "rb");
    std::fseek(f, 0, SEEK_END);
    const long s = std::ftell(f);
    std::fclose(f);
    return s;
  }();
  ASSERT_EQ(::truncate(kPath.c_str(), size - 20), 0);  // the last event cut short
  std::ostringstream csv;
  const MeasurementExport e = ExportMeasurementCsv(kPath, csv);
  EXPECT_TRUE(e.damaged);
  EXPECT_GT(e.damage_offset, 0);
  EXPECT_EQ(e.rows, 1);  // the Lz row before the damage
  const LogSummary summary = SummarizeLog(kPath);
  EXPECT_TRUE(summary.damaged);
  EXPECT_EQ(summary.channels.at("EDSP_SETPOINT").messages, 2);
  ::unlink(kPath.c_str());
}

TEST(MeasurementExport, MissingLogIsNamed) {
  std::ostringstream csv;
  try {
    ExportMeasurementCsv("/nonexistent/run.lcmlog", csv);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/run.lcmlog"), std::string::npos);
  }
}

}  // namespace
}  // namespace edsp
