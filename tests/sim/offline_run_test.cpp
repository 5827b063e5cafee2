// edsp-sim rig's engine: the log holds every channel the live logger would
// record, the measurement CSV one row per tracker sample, each row beside the
// setpoint of its own instant (no effect: point A exactly where the model
// puts it, in motion too), and a rig with an effect measurably off.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/logger/log_summary.h"
#include "edsp/sim/offline_run.h"
#include "scratch_dir.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

struct CsvStats {
  std::int64_t rows = 0;
  double max_error_m = 0.0;  // |point − A(pose_cmd)|
};

CsvStats ReadMeasurement(const std::string& path, const PlatformModel& model) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("time_s,run,pose_cmd_x_m", 0), 0u) << line;
  CsvStats stats;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.size() != 30) {
      ADD_FAILURE() << "row of " << cells.size() << " cells: " << line;
      continue;
    }
    // The offline stack's deterministic clock never stalls the drives.
    EXPECT_EQ(cells[29], "0") << "a timing_event offline: " << line;
    // No calibration runs: the kinematics took no correction off.
    for (std::size_t k = 20; k < 26; ++k) EXPECT_EQ(cells[k], "0") << "leg_corr: " << line;
    Vector6 q;
    for (int k = 0; k < 6; ++k) q(k) = std::stod(cells[static_cast<std::size_t>(2 + k)]);
    const Vector3 point(std::stod(cells[26]), std::stod(cells[27]), std::stod(cells[28]));
    stats.max_error_m = std::max(stats.max_error_m, (point - model.ObservationPoint(Pose::FromVector(q))).norm());
    ++stats.rows;
  }
  return stats;
}

class OfflineRunTest : public ::testing::Test {
 protected:
  void TearDown() override { std::filesystem::remove_all(dir_); }
  OfflineRunOptions Options() const {
    OfflineRunOptions o;
    o.motions = {"Lz", "Rz"};
    o.paper.stops = 2;
    o.paper.dwell_s = 0.2;
    o.paper.max_speed_m_s = 0.25;
    o.paper.max_speed_rad_s = 0.4;
    o.tracker.rate_hz = 100.0;
    o.out_dir = dir_;
    return o;
  }
  const std::string dir_ = test_support::ScratchRoot() + "/offline_run";
  const std::string source_ = SourceDir();
};

TEST_F(OfflineRunTest, LogAndMeasurementOfARigBuiltToTheModel) {
  RigEffects ideal;
  ideal.servo_lag.enabled = false;  // built to the model, ideal drive included
  const OfflineRunResult r = RunOffline(source_ + "/config/huang2021.toml", ideal, Options());
  EXPECT_EQ(r.faults, 0);
  EXPECT_GT(r.duration_s, 10.0);
  const LogSummary log = SummarizeLog(r.log_path);
  EXPECT_FALSE(log.damaged);
  EXPECT_EQ(log.channels.at("EDSP_SETPOINT").messages, r.cycles);
  EXPECT_EQ(log.channels.at("EDSP_LEG_COMMAND").messages, r.cycles);
  EXPECT_EQ(log.channels.at("EDSP_LEG_STATE").messages, r.cycles);
  EXPECT_EQ(log.channels.at("EDSP_TRACKER").messages, r.tracker_samples);
  EXPECT_EQ(log.channels.at("EDSP_CONFIG").messages, 1);
  EXPECT_NEAR(static_cast<double>(r.tracker_samples), r.duration_s * 100.0, 2.0);
  for (const auto& [name, c] : log.channels) EXPECT_EQ(c.seq_gaps, 0) << name;
  const CsvStats csv = ReadMeasurement(r.csv_path, PlatformModel(Huang2021Config()));
  EXPECT_GE(csv.rows, r.tracker_samples - 1);
  // In motion too (up to 0.25 m/s): each row is the same instant.
  EXPECT_LT(csv.max_error_m, 1e-6);
}

TEST_F(OfflineRunTest, TheExampleRigDepartsFromTheModel) {
  OfflineRunOptions o = Options();
  o.tracker.noise_sigma_m = 10e-6;
  o.tracker.seed = 7;
  const OfflineRunResult r = RunOffline(source_ + "/config/huang2021-rig-effects.toml", o);
  EXPECT_EQ(r.faults, 0);
  const CsvStats csv = ReadMeasurement(r.csv_path, PlatformModel(Huang2021Config()));
  EXPECT_GT(csv.max_error_m, 100e-6);  // tens to hundreds of µm
  EXPECT_LT(csv.max_error_m, 2e-3);
  // The same seed gives the same data.
  const std::string first = r.csv_path + ".first";
  std::filesystem::rename(r.csv_path, first);
  RunOffline(source_ + "/config/huang2021-rig-effects.toml", o);
  std::ifstream a(first), b(r.csv_path);
  std::stringstream ta, tb;
  ta << a.rdbuf();
  tb << b.rdbuf();
  EXPECT_EQ(ta.str(), tb.str());
}

TEST_F(OfflineRunTest, BadInputsAreNamed) {
  OfflineRunOptions o = Options();
  EXPECT_THROW(RunOffline(source_ + "/config/no-such.toml", o), ConfigError);
  o.motions = {"Lq"};
  EXPECT_THROW(RunOffline(source_ + "/config/huang2021.toml", o), std::invalid_argument);
  o = Options();
  o.out_dir = "/proc/edsp_no/dir";
  try {
    RunOffline(source_ + "/config/huang2021.toml", o);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/edsp_no/dir"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

TEST_F(OfflineRunTest, PerEffectErrorsOfTheExampleRig) {
  OfflineRunOptions o = Options();
  const std::vector<EffectError> table = PerEffectErrors(source_ + "/config/huang2021-rig-effects.toml", o);
  ASSERT_EQ(table.size(), 8u);  // every effect of the example but passive_rotation
  for (const EffectError& e : table) {
    EXPECT_GT(e.max_error_m, 1e-6) << e.effect;
    EXPECT_LT(e.max_error_m, 2e-3) << e.effect;
    EXPECT_LE(e.rms_error_m, e.max_error_m) << e.effect;
    EXPECT_TRUE(std::filesystem::exists(dir_ + "/" + e.effect + "/measurement.csv")) << e.effect;
  }
}

}  // namespace
}  // namespace edsp
