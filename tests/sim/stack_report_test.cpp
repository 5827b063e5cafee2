// The live-stack table from a log written here with known errors: dwells
// found by segment, the tracker averaged over the settled part only, the
// displacement along the motion's axis, the PR mode from the leg commands,
// the model's prediction from PointAError, and the plots as real PNGs.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "log_builder.h"  // tests/support
#include "edsp/kinematics/config.h"
#include "edsp/leg_command_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/pose_setpoint_v1_t.hpp"
#include "edsp/sim/paper_table.h"
#include "edsp/sim/stack_report.h"
#include "edsp/tracker_point_t.hpp"
#include "scratch_dir.h"
#include "platform_models.h"

namespace edsp {
namespace {

using test_support::LogBuilder;

// The setpoints' layout: today's, or the one logs recorded before setpoints
// carried their phase (the dwell told by its label alone).
enum class Layout { kToday, kBeforePhase };

class RunLog {
 public:
  RunLog(const std::string& path, const PlatformModel& model, Layout layout = Layout::kToday)
      : b_(path), model_(model), layout_(layout) {}
  void Command(std::int8_t mode) {
    leg_command_t c{};
    c.pr_mode = mode;
    b_.Add("EDSP_LEG_COMMAND", c);
  }
  // `ms` setpoints 1 ms apart; from `bad_until_ms` on, the tracker reads
  // point A of the pose plus `offset`, before it something far off.
  void Segment(const std::string& name, std::int8_t phase, int segment, const Vector6& pose, int ms,
               const Vector3& offset, int bad_until_ms) {
    const Vector3 a = model_.ObservationPoint(Pose::FromVector(pose));
    for (int k = 0; k < ms; ++k, utime_ += 1000) {
      pose_setpoint_t sp{};
      sp.utime = utime_;
      sp.trajectory = name;
      sp.segment = segment;
      sp.phase = phase;
      for (int i = 0; i < 6; ++i) sp.pose[i] = pose(i);
      AddSetpoint(sp);
      tracker_point_t t{};
      t.utime = utime_ + 200;
      t.valid = true;
      const Vector3 p = k < bad_until_ms ? a + Vector3(0.01, 0, 0) : a + offset;
      for (int i = 0; i < 3; ++i) t.point_m[i] = p(i);
      b_.Add("EDSP_TRACKER", t);
      if (k % 7 == 3) {  // an invalid sample (beam broken) is never averaged
        t.valid = false;
        t.point_m[0] = 99.0;
        b_.Add("EDSP_TRACKER", t);
      }
    }
  }

 private:
  void AddSetpoint(const pose_setpoint_t& sp) {
    if (layout_ == Layout::kToday) return b_.Add("EDSP_SETPOINT", sp);
    pose_setpoint_v1_t old{};
    old.utime = sp.utime;
    old.trajectory = sp.trajectory;
    old.segment = sp.segment;
    for (int i = 0; i < 6; ++i) old.pose[i] = sp.pose[i];
    b_.Add("EDSP_SETPOINT", old);
  }

  LogBuilder b_;
  const PlatformModel& model_;
  Layout layout_;
  std::int64_t utime_ = 1000000;
};

constexpr std::int8_t kMove = pose_setpoint_t::PHASE_MOVE;
constexpr std::int8_t kDwell = pose_setpoint_t::PHASE_DWELL;

// Two dwells of Lz and Rz between moves, the last cut short.
void WriteTwoDwells(RunLog& run, const Vector6& home, const Vector6& up, const Vector6& yawed) {
  run.Command(leg_command_t::PR_NONE);
  run.Segment("Lz/move 1", kMove, 0, home, 50, Vector3::Zero(), 50);
  run.Segment("Lz/dwell 1", kDwell, 1, up, 400, Vector3(3e-6, -1e-6, 2e-6), 150);  // bad first 150 ms
  run.Segment("Rz/move 1", kMove, 2, up, 30, Vector3::Zero(), 30);
  run.Command(leg_command_t::PR_SIGNED);
  run.Segment("Rz/dwell 1", kDwell, 3, yawed, 200, Vector3(0, 0, -5e-6), 0);
  run.Segment("Rz/move 2", kMove, 4, home, 10, Vector3::Zero(), 10);
  run.Segment("Rz/dwell 2", kDwell, 5, home, 100, Vector3::Zero(), 0);  // cut short: not a stop
}

class StackReportTest : public ::testing::Test {
 protected:
  void TearDown() override {
    std::filesystem::remove(log_);
    std::filesystem::remove_all(plots_);
  }
  // Two dwells of Lz and Rz written in `layout` (WriteTwoDwells), read back.
  DwellErrors TwoDwellsIn(Layout layout) {
    {
      RunLog run(log_, model_, layout);
      WriteTwoDwells(run, home_, up_, yawed_);
    }
    return DwellErrorsFromLog(log_, model_);
  }

  const PlatformModel model_ = test_support::Huang2021Model();
  const Vector6 home_ = model_.home_pose().ToVector();
  const Vector6 up_ = home_ + 0.25 * Vector6::Unit(2);
  const Vector6 yawed_ = home_ - 0.3 * Vector6::Unit(5);
  const std::string log_ = test_support::ScratchRoot() + "/stack_report.lcmlog";
  const std::string plots_ = test_support::ScratchRoot() + "/stack_plots";
};

TEST_F(StackReportTest, DwellsAveragedOverTheirSettledHalfWithModeAndDisplacement) {
  const DwellErrors e = TwoDwellsIn(Layout::kToday);
  EXPECT_FALSE(e.damaged);
  ASSERT_EQ(e.dwells.size(), 2u);
  const DwellError& lz = e.dwells[0];
  EXPECT_EQ(lz.motion, "Lz");
  EXPECT_EQ(lz.segment, "Lz/dwell 1");
  EXPECT_EQ(lz.pr_mode, PrMode::kNone);
  EXPECT_NEAR(lz.displacement, 0.25, 1e-12);
  EXPECT_NEAR((lz.error_m - Vector3(3e-6, -1e-6, 2e-6)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(lz.samples, 200, 2);  // the last half of 400 ms, valid samples only
  const DwellError& rz = e.dwells[1];
  EXPECT_EQ(rz.motion, "Rz");
  EXPECT_EQ(rz.pr_mode, PrMode::kSigned);
  EXPECT_NEAR(rz.displacement, -0.3, 1e-12);
  EXPECT_NEAR(rz.error_norm_m(), 5e-6, 1e-12);

  const std::vector<StackTableRow> rows = StackTable(e.dwells, model_);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].motion, "Lz");
  EXPECT_EQ(rows[0].mode, PrMode::kNone);
  EXPECT_EQ(rows[0].stops, 1);
  EXPECT_NEAR(rows[0].max_measured_m, std::sqrt(14.0) * 1e-6, 1e-12);
  EXPECT_DOUBLE_EQ(rows[0].max_predicted_m, PointAError(model_, Pose::FromVector(up_), PrMode::kNone));
  EXPECT_GT(rows[0].max_predicted_m, 1e-5);  // the PR miss without compensation
  EXPECT_LT(rows[1].max_predicted_m, 1e-8);  // signed: none left
  const std::string text = FormatStackTable(rows);
  EXPECT_NE(text.find("none mm"), std::string::npos) << text;
  EXPECT_NE(text.find("signed mm"), std::string::npos) << text;
  EXPECT_NE(text.find("0.0037"), std::string::npos) << text;  // √14 µm in mm

  const std::vector<std::string> pngs = WriteStackPlots(e.dwells, model_, plots_);
  ASSERT_EQ(pngs.size(), 2u);
  for (const std::string& png : pngs) {
    std::ifstream in(png, std::ios::binary);
    char magic[8] = {};
    in.read(magic, 8);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG") << png;
    EXPECT_GT(std::filesystem::file_size(png), 2000u) << png;
  }
}

// A dwell is what the setpoint's phase says, whatever its label: a
// trajectory CSV's segment may be named anything.
TEST_F(StackReportTest, TheSetpointsPhaseNotTheirLabelMakesADwell) {
  Vector6 up = home_;
  up(2) += 0.1;
  {
    RunLog run(log_, model_);
    run.Command(leg_command_t::PR_NONE);
    run.Segment("Lz/dwell 1", kMove, 0, home_, 100, Vector3::Zero(), 0);  // a move, whatever its name
    run.Segment("csv/pause", kDwell, 1, up, 200, Vector3(0, 2e-6, 0), 0);
    run.Segment("csv/back", kMove, 2, home_, 10, Vector3::Zero(), 0);
  }
  const DwellErrors e = DwellErrorsFromLog(log_, model_);
  ASSERT_EQ(e.dwells.size(), 1u);
  EXPECT_EQ(e.dwells[0].segment, "csv/pause");
  EXPECT_NEAR(e.dwells[0].error_m.y(), 2e-6, 1e-12);
}

// A log recorded before setpoints carried their phase reads the same
// dwells, told by the labels its planner wrote.
TEST_F(StackReportTest, ALogOfTheOlderSetpointLayoutReadsTheSameDwells) {
  const DwellErrors today = TwoDwellsIn(Layout::kToday);
  const DwellErrors before = TwoDwellsIn(Layout::kBeforePhase);
  ASSERT_EQ(today.dwells.size(), 2u);
  ASSERT_EQ(before.dwells.size(), today.dwells.size());
  for (std::size_t k = 0; k < today.dwells.size(); ++k) {
    EXPECT_EQ(before.dwells[k].segment, today.dwells[k].segment);
    EXPECT_EQ(before.dwells[k].samples, today.dwells[k].samples);
    EXPECT_EQ(before.dwells[k].error_m, today.dwells[k].error_m);
  }
}

TEST_F(StackReportTest, MissingLogAndUnwritablePlotsAreNamed) {
  try {
    DwellErrorsFromLog("/nonexistent/run.lcmlog", model_);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/run.lcmlog"), std::string::npos);
  }
  std::vector<DwellError> one(1);
  one[0].motion = "Lz";
  one[0].target = home_;
  try {
    WriteStackPlots(one, model_, "/proc/edsp_no/plots");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/edsp_no/plots"), std::string::npos);
  }
}

}  // namespace
}  // namespace edsp
