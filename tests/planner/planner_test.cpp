// Trajectories: boundary conditions, derivatives against finite differences,
// limits; sequences; the paper motions; CSV files; the planner's clock.
#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/planner/csv_trajectory.h"
#include "edsp/planner/paper_motions.h"
#include "edsp/planner/planner.h"

namespace edsp {
namespace {

Vector6 Home() { return PlatformModel(Huang2021Config()).home_pose().ToVector(); }

Vector6 Offset(int axis, double value) {
  Vector6 q = Home();
  q(axis) += value;
  return q;
}

// Velocity and acceleration against central differences of the trajectory.
void ExpectConsistentDerivatives(const Trajectory& t) {
  const double h = 1e-5;
  for (double s = 0.01; s < t.duration_s() - 0.01; s += t.duration_s() / 37.0) {
    const Vector6 v = (t.Sample(s + h).pose - t.Sample(s - h).pose) / (2 * h);
    const Vector6 a = (t.Sample(s + h).velocity - t.Sample(s - h).velocity) / (2 * h);
    EXPECT_LT((t.Sample(s).velocity - v).cwiseAbs().maxCoeff(), 1e-6) << "t = " << s;
    EXPECT_LT((t.Sample(s).acceleration - a).cwiseAbs().maxCoeff(), 1e-4) << "t = " << s;
  }
}

TEST(QuinticMove, StartsAndEndsAtRestOnItsEndpoints) {
  const QuinticMove move(Home(), Offset(2, 0.3), 2.0);
  EXPECT_EQ(move.Sample(0.0).pose, Home());
  EXPECT_LT((move.Sample(2.0).pose - Offset(2, 0.3)).norm(), 1e-15);
  for (double t : {0.0, 2.0}) {
    EXPECT_LT(move.Sample(t).velocity.norm(), 1e-15);
    EXPECT_LT(move.Sample(t).acceleration.norm(), 1e-12);
  }
  EXPECT_LT((move.Sample(1.0).pose - Offset(2, 0.15)).norm(), 1e-15);  // symmetric
  ExpectConsistentDerivatives(move);
}

TEST(QuinticMove, WithinLimitsPeaksAtTheSpeedLimit) {
  const QuinticMove move = QuinticMove::WithinLimits(Home(), Offset(0, 0.4), 0.1, 0.2);
  double peak = 0.0;
  for (double t = 0.0; t <= move.duration_s(); t += 1e-3) {
    peak = std::max(peak, move.Sample(t).velocity.head<3>().norm());
  }
  EXPECT_LE(peak, 0.1 + 1e-12);
  EXPECT_GT(peak, 0.0999);
  EXPECT_THROW(QuinticMove(Home(), Home(), 0.0), std::invalid_argument);
}

TEST(Sinusoid, FadesInAndOutAndHasConsistentDerivatives) {
  const Sinusoid wave(Home(), 5, 0.2, 0.5, 4);
  EXPECT_DOUBLE_EQ(wave.duration_s(), 8.0);
  for (double t : {0.0, 8.0}) {
    EXPECT_LT((wave.Sample(t).pose - Home()).norm(), 1e-12);
    EXPECT_LT(wave.Sample(t).velocity.norm(), 1e-12);
  }
  EXPECT_NEAR(wave.Sample(2.5).pose(5) - Home()(5), 0.2, 1e-12);  // full amplitude mid-way
  ExpectConsistentDerivatives(wave);
  EXPECT_THROW(Sinusoid(Home(), 6, 0.1, 1.0, 3), std::invalid_argument);
}

TEST(TrajectorySequence, RefusesJumpsAndLocatesSegments) {
  TrajectorySequence seq;
  seq.Append("up", std::make_unique<QuinticMove>(Home(), Offset(2, 0.1), 1.0));
  seq.Append("stay", std::make_unique<Dwell>(Offset(2, 0.1), 0.5));
  EXPECT_THROW(seq.Append("teleport", std::make_unique<Dwell>(Home(), 1.0)), std::invalid_argument);
  EXPECT_DOUBLE_EQ(seq.duration_s(), 1.5);
  EXPECT_EQ(seq.SegmentAt(0.5), 0);
  EXPECT_EQ(seq.SegmentAt(1.2), 1);
  EXPECT_EQ(seq.SegmentAt(99.0), 1);
  EXPECT_EQ(seq.SegmentName(1), "stay");
  EXPECT_LT((seq.Sample(99.0).pose - Offset(2, 0.1)).norm(), 1e-15);  // holds at the end
}

TEST(PaperMotions, VisitEveryStopAcrossTheRangeAndReturnHome) {
  TrajectorySequence seq;
  PaperMotionOptions options;
  AppendPaperMotion("Rz", Home(), options, &seq);
  std::vector<double> dwell_yaw;
  for (int k = 0; k < seq.size(); ++k) {
    if (seq.SegmentName(k).find("/dwell") != std::string::npos) {
      // Sample the middle of the dwell through the sequence.
      double start = 0.0;
      for (double t = 0.0; seq.SegmentAt(t) != k; t += 1e-3) start = t;
      dwell_yaw.push_back(seq.Sample(start + 0.5).pose(5));
    }
  }
  ASSERT_EQ(dwell_yaw.size(), 6u);  // 5 stops + home
  EXPECT_NEAR(dwell_yaw.front(), -M_PI / 6, 1e-12);
  EXPECT_NEAR(dwell_yaw[4], M_PI / 6, 1e-12);
  EXPECT_NEAR(dwell_yaw.back(), 0.0, 1e-12);
  EXPECT_LT((seq.EndPose() - Home()).norm(), 1e-15);
  EXPECT_THROW(AppendPaperMotion("Lq", Home(), options, &seq), std::invalid_argument);
}

TEST(CheckTrajectory, NamesTheSegmentTimeAndLimit) {
  TrajectorySequence seq;
  PaperMotionOptions options;
  options.linear_range_m = 0.8;  // beyond the legs' stroke
  AppendPaperMotion("Lz", Home(), options, &seq);
  try {
    CheckTrajectory(PlatformModel(Huang2021Config()), seq);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("Lz/move 1"), std::string::npos) << message;
    EXPECT_NE(message.find("leg_min_m"), std::string::npos) << message;
  }
}

// The demo once ran Rz at 0.7 rad/s: legs at > 0.5 m/s, refused mid-motion by
// the bridge as jumps. The planner now refuses it before the first setpoint,
// with the speed computed independently here from finite differences of IK.
TEST(CheckTrajectory, RefusesLegsFasterThanTheDrivesFollow) {
  const PlatformModel model(Huang2021Config());
  PaperMotionOptions fast;
  fast.max_speed_rad_s = 0.7;
  TrajectorySequence too_fast;
  AppendPaperMotion("Rz", Home(), fast, &too_fast);
  double fastest = 0.0;
  for (double t = 0.0; t + 1e-3 <= too_fast.duration_s(); t += 1e-3) {
    const Vector6 a = model.Solve(Pose::FromVector(too_fast.Sample(t).pose)).length_m;
    const Vector6 b = model.Solve(Pose::FromVector(too_fast.Sample(t + 1e-3).pose)).length_m;
    fastest = std::max(fastest, (b - a).cwiseAbs().maxCoeff() / 1e-3);
  }
  ASSERT_GT(fastest, 0.5);  // the case is real
  try {
    CheckTrajectory(model, too_fast);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("Rz/move"), std::string::npos) << message;
    EXPECT_NE(message.find("leg_speed_max_m_s = 0.5"), std::string::npos) << message;
  }
  PaperMotionOptions slow;
  slow.max_speed_rad_s = 0.4;  // what the demo runs
  TrajectorySequence fine;
  AppendPaperMotion("Rz", Home(), slow, &fine);
  EXPECT_NO_THROW(CheckTrajectory(model, fine));
  PlatformConfig faster_drives = Huang2021Config();
  faster_drives.limits.leg_speed_max_m_s = 1.0;
  EXPECT_NO_THROW(CheckTrajectory(PlatformModel(faster_drives), too_fast));
}

TEST(Planner, FollowsTheAbsoluteClockAndHoldsAtTheEnd) {
  auto seq = std::make_unique<TrajectorySequence>();
  seq->Append("up", std::make_unique<QuinticMove>(Home(), Offset(2, 0.1), 1.0));
  seq->Append("stay", std::make_unique<Dwell>(Offset(2, 0.1), 0.5));
  Planner planner(PlatformModel(Huang2021Config()), std::move(seq), 42);
  const std::int64_t start = 5000000;
  planner.Start(start);
  const pose_setpoint_t first = planner.Step(start + 100000);
  // A late cycle lands where the clock says, not one step after the last.
  const pose_setpoint_t late = planner.Step(start + 600000);
  const QuinticMove reference(Home(), Offset(2, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(late.pose[2], reference.Sample(0.6).pose(2));
  EXPECT_EQ(late.seq, first.seq + 1);
  EXPECT_EQ(late.session_id, 42);
  EXPECT_EQ(late.trajectory, "up");
  EXPECT_EQ(late.phase, pose_setpoint_t::PHASE_MOVE);
  EXPECT_FALSE(planner.Finished(start + 1400000));
  const pose_setpoint_t after = planner.Step(start + 9000000);
  EXPECT_TRUE(planner.Finished(start + 9000000));
  EXPECT_EQ(after.trajectory, "stay");
  EXPECT_EQ(after.phase, pose_setpoint_t::PHASE_DWELL);  // by the segment's type, not its name
  EXPECT_NEAR(after.pose[2], Home()(2) + 0.1, 1e-15);
  EXPECT_EQ(after.velocity[2], 0.0);
}

TEST(CsvTrajectory, InterpolatesAndRejectsBadFilesByLineAndColumn) {
  const std::string head = "# exported\nyaw_rad,time_s,x_m,y_m,z_m,roll_rad,pitch_rad,note\n";
  const CsvTrajectory t = CsvTrajectory::Parse(head + "0,0,0,0,1.511,0,0,a\n0.2,1,0.1,0,1.511,0,0,b\n", "motion.csv");
  EXPECT_DOUBLE_EQ(t.duration_s(), 1.0);
  EXPECT_NEAR(t.Sample(0.25).pose(5), 0.05, 1e-15);
  EXPECT_NEAR(t.Sample(0.25).velocity(0), 0.1, 1e-15);
  auto error_of = [](const std::string& text) {
    try {
      CsvTrajectory::Parse(text, "motion.csv");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of("time_s,x_m\n0,0\n").find("lacks column y_m"), std::string::npos);
  EXPECT_NE(error_of(head + "0,0,0,0,1.5,0,0,a\n0,1,nan,0,1.5,0,0,b\n").find("motion.csv:4:3: x_m"), std::string::npos);
  EXPECT_NE(error_of(head + "0,1,0,0,1.5,0,0,a\n0,1,0,0,1.5,0,0,b\n").find("does not increase"), std::string::npos);
  EXPECT_NE(error_of(head).find("at least two rows"), std::string::npos);
}

}  // namespace
}  // namespace edsp
