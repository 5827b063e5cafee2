// The virtual rig: servo loops settle and respect the torque limit, the
// platform sits where the rig's TRUE geometry and PR put it, the tracker
// emulator measures point A in its own frame with the configured noise.
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/kinematics/config.h"
#include "edsp/rig/virtual_rig.h"

namespace edsp {
namespace {

DriveSetpoint AnglesFor(const PlatformModel& model, const Vector6& encoder_lengths) {
  DriveSetpoint s;
  for (int i = 0; i < kNumLegs; ++i) {
    s.motor_angle_rad[i] = model.MotorAngleFromLength(i, encoder_lengths(i));
  }
  return s;
}

void RunFor(VirtualRig& rig, double seconds) {
  for (int k = 0; k < static_cast<int>(seconds * 1000); ++k) ASSERT_TRUE(rig.Advance(1e-3));
}

TEST(VirtualRig, ServoSettlesOnATargetWithinTheTorqueLimit) {
  RigParameters p = IdealRig(Huang2021Config());
  p.effects.servo_lag.enabled = true;
  VirtualRig rig(p);
  DriveSetpoint target;
  target.motor_angle_rad.fill(10.0);  // 16 mm of leg travel
  rig.SetTarget(target, true);
  double peak_acceleration = 0.0, peak_velocity = 0.0, previous_velocity = 0.0;
  for (int k = 0; k < 1000; ++k) {
    ASSERT_TRUE(rig.Advance(1e-3));
    const double v = rig.Feedback().motor_velocity_rad_s[0];
    peak_acceleration = std::max(peak_acceleration, std::abs(v - previous_velocity) / 1e-3);
    peak_velocity = std::max(peak_velocity, std::abs(v));
    previous_velocity = v;
  }
  for (int i = 0; i < kNumLegs; ++i) EXPECT_NEAR(rig.Feedback().motor_angle_rad[i], 10.0, 1e-6);
  // Braking, viscous friction adds to the saturated torque.
  const double limit = (p.effects.servo_lag.torque_limit_N_m + p.effects.servo_lag.viscous_N_m_s * peak_velocity) /
                       p.effects.servo_lag.inertia_kg_m2;
  EXPECT_LE(peak_acceleration, limit * 1.001);
  EXPECT_GT(peak_acceleration, limit * 0.9);  // a 10 rad step saturates it
}

TEST(VirtualRig, DisabledDrivesDoNotMove) {
  VirtualRig rig(IdealRig(Huang2021Config()));
  DriveSetpoint target;
  target.motor_angle_rad.fill(5.0);
  rig.SetTarget(target, false);
  RunFor(rig, 0.2);
  EXPECT_EQ(rig.Feedback().motor_angle_rad[0], 0.0);
  EXPECT_EQ(rig.Feedback().status[0], DriveStatus::kDisabled);
}

TEST(VirtualRig, PlatformSitsWhereTheTrueSignedPrPutsIt) {
  const PlatformModel model(Huang2021Config());
  VirtualRig rig(IdealRig(model.config()));
  Pose target = model.home_pose();
  target.p_BoMo_B << 0.02, -0.01, 1.52;
  target.rpy_rad << 0.01, 0.02, 0.05;
  rig.SetTarget(AnglesFor(model, model.EncoderLengths(target)), true);
  RunFor(rig, 1.0);
  EXPECT_LT((rig.true_pose().ToVector() - target.ToVector()).cwiseAbs().maxCoeff(), 1e-9);
  // Commanding plain IK lengths instead leaves the PR error in the pose.
  rig.SetTarget(AnglesFor(model, model.LegLengths(target)), true);
  RunFor(rig, 1.0);
  EXPECT_GT((rig.true_pose().ToVector() - target.ToVector()).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(VirtualRig, ScrewsAdvanceByTheirTrueLeadNotTheNominalOne) {
  const PlatformModel nominal(Huang2021Config());
  RigParameters p = IdealRig(nominal.config());
  p.effects.lead_error.enabled = true;
  p.effects.lead_error.epsilon.fill(0.01);  // the screws advance 1% more than nominal
  VirtualRig rig(p);
  Pose target = nominal.home_pose();
  target.p_BoMo_B.z() += 0.1;
  rig.SetTarget(AnglesFor(nominal, nominal.EncoderLengths(target)), true);
  RunFor(rig, 1.0);
  // Legs travel 1% further than commanded: about 1 mm too high.
  EXPECT_NEAR(rig.true_pose().p_BoMo_B.z() - target.p_BoMo_B.z(), 0.001, 2e-4);
}

TEST(VirtualRig, TrackerMeasuresPointAInItsOwnFrame) {
  RigParameters p = IdealRig(Huang2021Config());
  p.tracker.X_TB.p_BoMo_B << 3.0, -1.0, 0.2;
  p.tracker.X_TB.rpy_rad << 0.0, 0.0, 0.7;
  VirtualRig rig(p);
  ASSERT_TRUE(rig.Advance(1e-3));
  tracker_point_t point;
  ASSERT_TRUE(rig.TrackerSample(1000, &point));
  const Vector3 a_B = rig.true_model().ObservationPoint(rig.true_pose());
  const Vector3 expected = PointInBase(p.tracker.X_TB, a_B);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(point.point_m[k], expected(k), 1e-12);
  EXPECT_TRUE(point.valid);
}

std::vector<double> TrackerX(const RigParameters& p, int steps) {
  VirtualRig rig(p);
  std::vector<double> xs;
  for (int k = 1; k <= steps; ++k) {
    rig.Advance(1e-3);
    tracker_point_t point;
    if (rig.TrackerSample(k * 1000, &point)) xs.push_back(point.point_m[0]);
  }
  return xs;
}

TEST(VirtualRig, TrackerNoiseRateAndSeed) {
  RigParameters p = IdealRig(Huang2021Config());
  p.tracker.noise_sigma_m = 1e-5;
  p.tracker.rate_hz = 250.0;
  p.tracker.seed = 7;
  const std::vector<double> xs = TrackerX(p, 8000);
  EXPECT_NEAR(static_cast<double>(xs.size()), 2000.0, 1.0);  // 250 Hz over 8 s
  double mean = 0.0, var = 0.0;
  for (double x : xs) mean += x / static_cast<double>(xs.size());
  for (double x : xs) var += (x - mean) * (x - mean) / static_cast<double>(xs.size() - 1);
  EXPECT_NEAR(std::sqrt(var), 1e-5, 1e-6);
  EXPECT_NEAR(mean, 1.2, 1e-6);                   // A at home is (1.2, 0, H) and the platform is still
  EXPECT_EQ(TrackerX(p, 400), TrackerX(p, 400));  // same seed, same run
  RigParameters other = p;
  other.tracker.seed = 8;
  EXPECT_NE(TrackerX(p, 400), TrackerX(other, 400));
}

TEST(InProcessRigBackend, MotionOnlyWhileActive) {
  VirtualRig rig(IdealRig(Huang2021Config()));
  InProcessRigBackend backend(&rig);
  std::string error;
  DriveSetpoint target;
  target.motor_angle_rad.fill(1.0);
  EXPECT_FALSE(backend.Write(0, target));
  EXPECT_FALSE(backend.Activate(&error));
  EXPECT_FALSE(error.empty());
  ASSERT_TRUE(backend.Configure(Huang2021Config(), &error));
  ASSERT_TRUE(backend.Activate(&error));
  EXPECT_TRUE(backend.Write(0, target));
  RunFor(rig, 0.5);
  DriveFeedback feedback;
  ASSERT_TRUE(backend.Read(0, &feedback));
  EXPECT_NEAR(feedback.motor_angle_rad[3], 1.0, 1e-6);
  backend.Deactivate();
  EXPECT_FALSE(backend.Write(0, target));
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

// The servo_lag effect's load: the platform's weight through the screw. A
// P-D loop sags under it by the load torque over kp (the hand calculation:
// each of the six symmetric legs carries m·g/(6·u_z)); integral action
// removes the sag.
TEST(VirtualRig, LoadedDriveSagsUnlessTheLoopIntegrates) {
  const PlatformConfig nominal = Huang2021Config();
  const PlatformModel model(nominal);
  const double m = 600.0;
  const double uz = model.Solve(model.home_pose()).u_B(2, 0);
  const double force = m * 9.81 / (6.0 * uz);
  const double torque = force * nominal.drive.lead_m / (2.0 * M_PI * nominal.drive.gear_ratio * 0.9);
  for (double integral_time_s : {0.0, 0.05}) {
    RigParameters p = IdealRig(nominal);
    p.effects.servo_lag.load_mass_kg = m;
    p.effects.servo_lag.integral_time_s = integral_time_s;
    VirtualRig rig(p);
    rig.SetTarget(DriveSetpoint{}, true);  // hold home
    RunFor(rig, 3.0);
    // The loop is tuned on what the motor moves: its inertia and a sixth of
    // the load through the screw (motor torque per newton of leg force,
    // lead / (2π · gear · η); the load's inertia at the motor carries η once).
    const double eta = p.effects.servo_lag.screw_efficiency;
    const double screw = nominal.drive.lead_m / (2.0 * M_PI * nominal.drive.gear_ratio * eta);
    const double inertia = p.effects.servo_lag.inertia_kg_m2 + m / 6.0 * screw * screw * eta;
    const double kp = inertia * std::pow(2.0 * M_PI * p.effects.servo_lag.bandwidth_hz, 2);
    for (int i = 0; i < kNumLegs; ++i) {
      const double angle = rig.Feedback().motor_angle_rad[i];
      if (integral_time_s == 0.0) {
        EXPECT_NEAR(angle, -torque / kp, 0.01 * torque / kp) << "leg " << i + 1;  // pushed back
      } else {
        EXPECT_LT(std::abs(angle), 1e-9) << "leg " << i + 1;
      }
    }
  }
}

// A drive is commissioned with its load on: its step response is the same
// with 600 kg on the legs as with none. Tuned on the bare motor, the
// payload's inertia (1.4× the motor's through this screw) would slow the
// loop by √2.4: a half-rise 1.55× as long.
TEST(VirtualRig, TheDriveLoopKeepsItsBandwidthUnderThePayload) {
  auto half_rise_s = [](double load_kg) {
    RigParameters p = IdealRig(Huang2021Config());
    p.effects.servo_lag.load_mass_kg = load_kg;
    p.effects.servo_lag.integral_time_s = 0.05;  // holds the weight: no sag before the step
    VirtualRig rig(p);
    rig.SetTarget(DriveSetpoint{}, true);
    RunFor(rig, 2.0);
    const double start = rig.Feedback().motor_angle_rad[0];
    DriveSetpoint step;
    step.motor_angle_rad.fill(0.1);
    rig.SetTarget(step, true);
    for (int k = 1; k <= 1000; ++k) {
      EXPECT_TRUE(rig.Advance(1e-3));
      if (rig.Feedback().motor_angle_rad[0] - start >= 0.05) return k * 1e-3;
    }
    return 1.0;
  };
  const double bare = half_rise_s(0.0), loaded = half_rise_s(600.0);
  EXPECT_LT(bare, 0.05);                         // a 50 Hz loop: a few milliseconds
  EXPECT_NEAR(loaded, bare, 0.1 * bare + 1e-3);  // within a tenth (and one step of the 1 ms loop)
}

// Dry friction: the motor stops where the loop's torque no longer beats
// it, short of the target by at most coulomb/kp, on the side it came from.
TEST(VirtualRig, CoulombFrictionLeavesADeadbandOnTheSideOfTheApproach) {
  RigParameters p = IdealRig(Huang2021Config());
  p.effects.servo_lag.coulomb_N_m = 0.05;
  VirtualRig rig(p);
  const double kp = p.effects.servo_lag.inertia_kg_m2 * std::pow(2.0 * M_PI * p.effects.servo_lag.bandwidth_hz, 2);
  const double band = 0.05 / kp;
  DriveSetpoint target;
  target.motor_angle_rad.fill(1.0);
  rig.SetTarget(target, true);
  RunFor(rig, 1.0);
  const double from_below = 1.0 - rig.Feedback().motor_angle_rad[0];
  EXPECT_GT(from_below, 0.01 * band);
  EXPECT_LE(from_below, band * 1.0001);
  EXPECT_LT(std::abs(rig.Feedback().motor_velocity_rad_s[0]), 1e-9);  // stopped
  rig.SetTarget(DriveSetpoint{}, true);
  RunFor(rig, 1.0);
  const double from_above = 0.0 - rig.Feedback().motor_angle_rad[0];
  EXPECT_LT(from_above, -0.01 * band);
  EXPECT_GE(from_above, -band * 1.0001);
}

// A process image that stops updating (the bridge frozen or killed while
// moving): the drives follow the last velocity feed-forward for the
// interpolation horizon only, then hold, and report it past the watchdog.
// With and without the servo: both drive models must stop.
TEST(VirtualRig, DrivesWithoutNewCommandsStopAfterTheInterpolationHorizon) {
  for (const bool servo : {false, true}) {
    RigParameters p = IdealRig(Huang2021Config());
    p.effects.servo_lag.enabled = servo;
    VirtualRig rig(p);
    DriveSetpoint moving;
    const double speed_rad_s = 100.0;  // about 0.16 m/s of leg
    double angle = 0.0;
    for (int k = 0; k < 200; ++k) {  // commands every cycle while moving
      moving.motor_angle_rad.fill(angle);
      moving.motor_velocity_rad_s.fill(speed_rad_s);
      rig.SetTarget(moving, true);
      ASSERT_TRUE(rig.Advance(1e-3));
      angle += speed_rad_s * 1e-3;
      EXPECT_FALSE(rig.watchdog_tripped());
    }
    // The commands stop. Where the target can end up: the last command plus
    // the horizon at that speed.
    const double last_command = angle - speed_rad_s * 1e-3;
    const double limit = last_command + speed_rad_s * p.watchdog.interpolation_horizon_s;
    double at_watchdog = 0.0;
    for (int k = 1; k <= 500; ++k) {
      ASSERT_TRUE(rig.Advance(1e-3));
      if (k == 20) at_watchdog = rig.Feedback().motor_angle_rad[0];
      EXPECT_EQ(rig.watchdog_tripped(), k + 1 > 20) << k;  // k + 1 ms since the last command
    }
    const DriveFeedback f = rig.Feedback();
    EXPECT_LT(f.motor_angle_rad[0], limit + 0.05 * speed_rad_s * 1e-3) << (servo ? "servo" : "ideal");
    EXPECT_GT(f.motor_angle_rad[0], last_command - 0.5) << "it did not run backwards either";
    EXPECT_NEAR(f.motor_angle_rad[0], at_watchdog, servo ? 0.5 : 1e-12) << "at rest after the watchdog";
    EXPECT_NEAR(f.motor_velocity_rad_s[0], 0.0, 1e-3);
    EXPECT_EQ(f.status[0], DriveStatus::kHolding);
    rig.SetTarget(moving, true);  // a command again: enabled, following
    EXPECT_FALSE(rig.watchdog_tripped());
    EXPECT_EQ(rig.Feedback().status[0], DriveStatus::kEnabled);
  }
}

// A rig emulator restarted after a crash continues where its predecessor's
// motors were (absolute encoders), not at home.
TEST(VirtualRig, ARestoredRigSitsWhereItsPredecessorsMotorsWere) {
  const PlatformConfig config = Huang2021Config();
  const PlatformModel model(config);
  VirtualRig before(IdealRig(config));
  Pose pose = model.home_pose();
  pose.p_BoMo_B += Vector3(0.01, -0.02, 0.03);
  before.SetTarget(AnglesFor(model, model.CompensatedLengths(pose, PrMode::kSigned)), true);
  RunFor(before, 2.0);  // the servo settles
  VirtualRig after(IdealRig(config));
  ASSERT_TRUE(after.RestoreDrives(before.Feedback().motor_angle_rad));
  EXPECT_LT((after.true_pose().p_BoMo_B - before.true_pose().p_BoMo_B).norm(), 1e-9);
  EXPECT_NEAR((after.true_pose().p_BoMo_B - model.home_pose().p_BoMo_B).norm(), 0.0374, 1e-3) << "not at home";
  const DriveFeedback f = after.Feedback();
  EXPECT_EQ(f.status[0], DriveStatus::kDisabled);
  EXPECT_EQ(f.motor_angle_rad, before.Feedback().motor_angle_rad);
  RunFor(after, 0.1);  // disabled: it stays
  EXPECT_LT((after.true_pose().p_BoMo_B - before.true_pose().p_BoMo_B).norm(), 1e-9);
}

}  // namespace
}  // namespace edsp
