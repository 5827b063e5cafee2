// The blind rig without effects is the nominal platform (checked against
// edsp's own kinematics), each effect leaves its signature, and the drawn
// scenarios cover the kinds and tracker settings they promise.
#include <cmath>
#include <algorithm>
#include <set>

#include <gtest/gtest.h>

#include "edsp/blindrig/blind_setup.h"
#include "edsp/diagnosis/measurement_data.h"
#include "edsp/kinematics/leg_effects.h"
#include "edsp/kinematics/platform_model.h"

namespace edsp::blind {
namespace {

TrackerOptions IdealTracker() {
  TrackerOptions t;
  t.noise_m = 0.0;
  t.frame = Vec6::Zero();
  t.rate_hz = 50.0;
  return t;
}

gap::MeasurementData Generate(const BlindEffects& effects, const TrackerOptions& tracker,
                              std::vector<std::string> motions = {"Lz", "Ry", "M1"}) {
  BlindRigSetup setup = SetupFromConfig(Huang2021Config());
  setup.motions = std::move(motions);
  return gap::ParseMeasurementCsv(GenerateMeasurementCsv(setup, effects, tracker), "blind rig");
}

// Largest distance of the measured point from where edsp's model puts A.
double LargestGapToModel(const gap::MeasurementData& data) {
  const PlatformModel model(Huang2021Config());
  double largest = 0.0;
  for (const gap::MeasurementRow& row : data.rows) {
    largest = std::max(largest, (row.point_m - model.ObservationPoint(Pose::FromVector(row.pose_cmd))).norm());
  }
  return largest;
}

TEST(BlindRig, WithoutEffectsThePointIsWhereEdspsModelPutsIt) {
  const gap::MeasurementData data = Generate({}, IdealTracker());
  ASSERT_EQ(data.runs, (std::vector<std::string>{"Lz", "Ry", "M1"}));
  EXPECT_GT(data.rows.size(), 1000u);
  // The CSV's 1 nm / 1 nrad resolution is the only difference left.
  EXPECT_LT(LargestGapToModel(data), 5e-9);
}

TEST(BlindRig, CommandsAreEdspsSignedCompensation) {
  const PlatformModel model(Huang2021Config());
  for (const gap::MeasurementRow& row : Generate({}, IdealTracker()).rows) {
    const Vector6 expected = model.CompensatedLengths(Pose::FromVector(row.pose_cmd), PrMode::kSigned);
    ASSERT_LT((row.leg_cmd_m - expected).cwiseAbs().maxCoeff(), 3e-9);
  }
}

// A controller calibration is called once per control step in order of
// time with the nominal command, its correction comes off the command, and
// the CSV records it; the legs follow the corrected command (a correction of
// +c on every leg at home lowers A as shorter legs do).
TEST(BlindRig, AControllerCalibrationComesOffTheCommandAndIsRecorded) {
  const Vec6 c = (Vec6() << 100e-6, 100e-6, 100e-6, 100e-6, 100e-6, 100e-6).finished();
  BlindRigSetup setup = SetupFromConfig(Huang2021Config());
  setup.motions = {"Lz", "M1"};
  const gap::MeasurementData nominal =
      gap::ParseMeasurementCsv(GenerateMeasurementCsv(setup, {}, IdealTracker()), "nominal");
  int calls = 0;
  double last_time_s = -1.0, worst_command_m = 0.0;
  const PlatformModel model(Huang2021Config());
  setup.calibration = [&](double time_s, const Vec6& pose, const Vec6&, const Vec6&, const Vec6& command_m) {
    ++calls;
    EXPECT_GT(time_s, last_time_s);
    last_time_s = time_s;
    const Vector6 expected = model.CompensatedLengths(Pose::FromVector(pose), PrMode::kSigned);
    worst_command_m = std::max(worst_command_m, (command_m - expected).cwiseAbs().maxCoeff());
    return c;
  };
  const gap::MeasurementData corrected =
      gap::ParseMeasurementCsv(GenerateMeasurementCsv(setup, {}, IdealTracker()), "corrected");
  EXPECT_GT(calls, 1000 * static_cast<int>(corrected.rows.size()) / 50 - 100) << "once per 1 kHz step";
  EXPECT_LT(worst_command_m, 1e-9) << "the nominal command is handed over";
  ASSERT_TRUE(corrected.has_correction);
  ASSERT_FALSE(nominal.has_correction);
  ASSERT_EQ(corrected.rows.size(), nominal.rows.size());
  for (std::size_t k = 0; k < corrected.rows.size(); ++k) {
    const gap::MeasurementRow &with = corrected.rows[k], &without = nominal.rows[k];
    ASSERT_LT((with.leg_cmd_m - (without.leg_cmd_m - c)).cwiseAbs().maxCoeff(), 2e-9);
    ASSERT_LT((with.leg_corr_m - c).cwiseAbs().maxCoeff(), 2e-9);
  }
  // At home (the first row), shorter legs lower A.
  EXPECT_LT(corrected.rows[0].point_m.z(), nominal.rows[0].point_m.z() - 50e-6);
}

// A motion given as samples is run as the rig's own: its own Lz and M1,
// sampled at the control rate, give the same measurement (an effect whose
// loads follow the acceleration on, so the second derivatives count too).
TEST(BlindRig, AMotionGivenAsSamplesRunsAsItsOwn) {
  BlindEffects effects;
  effects.stiffness_N_m = Vec6::Constant(20e6);
  effects.mass_kg = 800.0;
  effects.com_M = Vec3(0.0, 0.0, 0.2);
  effects.backlash_m = Vec6::Constant(30e-6);
  BlindRigSetup own = SetupFromConfig(Huang2021Config());
  own.motions = {"Lz", "M1"};
  BlindRigSetup sampled = own;
  for (const std::string& name : own.motions) {
    const BlindMotion motion = MotionNamed(own, name);
    SampledMotion m{name, own.control_rate_hz, {}, {}};
    const auto steps = static_cast<int>(std::round(motion.duration_s() * own.control_rate_hz));
    for (int k = 0; k <= steps; ++k) {
      m.poses.push_back(motion.Pose(k / own.control_rate_hz));
      m.accelerations.push_back(motion.Acceleration(k / own.control_rate_hz));
    }
    sampled.sampled_motions.push_back(std::move(m));
  }
  const gap::MeasurementData a = gap::ParseMeasurementCsv(GenerateMeasurementCsv(own, effects, IdealTracker()), "own");
  const gap::MeasurementData b =
      gap::ParseMeasurementCsv(GenerateMeasurementCsv(sampled, effects, IdealTracker()), "sampled");
  // Run by run: a sampled run ends on its last whole control step, up to a
  // step before its own, so it may hold one tracker sample less.
  double largest = 0.0;
  std::size_t compared = 0;
  for (const std::string& run : own.motions) {
    std::vector<const gap::MeasurementRow*> ra, rb;
    for (const gap::MeasurementRow& r : a.rows)
      if (a.runs[static_cast<std::size_t>(r.run)] == run) ra.push_back(&r);
    for (const gap::MeasurementRow& r : b.rows)
      if (b.runs[static_cast<std::size_t>(r.run)] == run) rb.push_back(&r);
    ASSERT_LE(std::max(ra.size(), rb.size()) - std::min(ra.size(), rb.size()), 1u) << run;
    for (std::size_t k = 0; k < std::min(ra.size(), rb.size()); ++k, ++compared) {
      largest = std::max(largest, (ra[k]->point_m - rb[k]->point_m).norm());
      ASSERT_LT((ra[k]->pose_cmd - rb[k]->pose_cmd).cwiseAbs().maxCoeff(), 1e-8) << run << " " << k;
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_LT(largest, 0.05e-6);
  EXPECT_THROW(BlindMotion(SampledMotion{"one", 1000.0, {Vec6::Zero()}, {Vec6::Zero()}}), std::invalid_argument);
  EXPECT_TRUE(IsBlindMotionName("Lz") && IsBlindMotionName("M12"));
  EXPECT_FALSE(IsBlindMotionName("calibration") || IsBlindMotionName("M") || IsBlindMotionName("Lw"));
}

TEST(BlindRig, EachEffectMovesThePointByARealisticAmount) {
  for (int index = 1; index < 30; ++index) {
    const BlindScenario s = DrawBlindScenario(11, index);
    if (s.kind == "none") continue;
    TrackerOptions tracker = IdealTracker();
    tracker.frame = s.tracker.frame;
    tracker.frame.head<3>().setZero(), tracker.frame.tail<3>().setZero();
    const double gap = LargestGapToModel(Generate(s.effects, tracker));
    // Above a good tracker's noise, below what a rig team would run
    // (a 10 Hz position loop without feed-forward lags by millimetres).
    EXPECT_GT(gap, 2e-6) << s.description;
    EXPECT_LT(gap, 10e-3) << s.description;
  }
}

// The benchmark's --encoders: forcing the encoder columns changes nothing
// else of a draw (the same effects, truth and tracker), so a run without
// encoders scores the same scenarios as the drawn one.
TEST(BlindRig, ForcingTheEncodersLeavesTheRestOfTheDrawAlone) {
  for (int index = 0; index < 10; ++index) {
    const BlindScenario drawn = DrawBlindScenario(5, index);
    for (const bool encoders : {true, false}) {
      const BlindScenario forced = DrawBlindScenario(5, index, encoders);
      EXPECT_EQ(forced.tracker.encoders, encoders);
      EXPECT_EQ(forced.truth, drawn.truth);
      EXPECT_EQ(forced.kind, drawn.kind);
      EXPECT_EQ(forced.tracker.rate_hz, drawn.tracker.rate_hz);
      EXPECT_EQ(forced.tracker.noise_m, drawn.tracker.noise_m);
      EXPECT_EQ(forced.tracker.seed, drawn.tracker.seed);
      EXPECT_EQ(forced.tracker.frame, drawn.tracker.frame);
      const std::string says = encoders ? "with encoders" : "without encoders";
      EXPECT_NE(forced.description.find(says), std::string::npos) << forced.description;
      if (forced.tracker.encoders == drawn.tracker.encoders) {
        EXPECT_EQ(forced.description, drawn.description);
      }
    }
  }
}

// A tracker clock that gains on the controller's (the out-of-vocabulary
// clock_drift) reads each instant as late as a constant offset equal to
// its lateness then would: drift × session time. The tracker's stand
// vibrates, so that the reading's own instant counts as well as the
// platform's.
TEST(BlindRig, AFreeRunningClockReadsAsLateAsItsDriftHasMadeIt) {
  BlindEffects vibrating;
  vibrating.floor_hz = 5.0;
  vibrating.floor_amplitude_m = 20e-6;
  BlindEffects drifting = vibrating;
  drifting.clock_drift = 2e-4;
  const gap::MeasurementData data = Generate(drifting, IdealTracker());
  // The row of the last run where the platform moves fastest.
  const gap::MeasurementRow* late = nullptr;
  double fastest = 0.0;
  for (std::size_t k = 1; k + 1 < data.rows.size(); ++k) {
    if (data.runs[static_cast<std::size_t>(data.rows[k].run)] != "M1") continue;
    const double step = (data.rows[k + 1].pose_cmd - data.rows[k - 1].pose_cmd).norm();
    if (step > fastest) fastest = step, late = &data.rows[k];
  }
  ASSERT_NE(late, nullptr);
  const auto same_stamp = [&](const gap::MeasurementData& other) {
    for (const gap::MeasurementRow& row : other.rows) {
      if (std::abs(row.time_s - late->time_s) < 1e-9) return row.point_m;
    }
    ADD_FAILURE() << "no row at " << late->time_s;
    return Vector3(Vector3::Zero());
  };
  TrackerOptions offset = IdealTracker();
  offset.time_offset_s = drifting.clock_drift * late->time_s;
  EXPECT_LT((same_stamp(Generate(vibrating, offset)) - late->point_m).norm(), 1e-8);
  EXPECT_GT((same_stamp(Generate(vibrating, IdealTracker())) - late->point_m).norm(), 1e-6);
}

// A target re-seated before each run (the out-of-vocabulary
// target_reseat) moves A by an offset fixed in the platform's frame {M}
// for the whole run, and another the next run: the readings' difference
// from the target left in place, turned back into {M} with the commanded
// pose's rotation, is one vector per run.
TEST(BlindRig, AReseatedTargetSitsApartByOneOffsetInThePlatformPerRun) {
  BlindEffects reseated;
  reseated.target_reseat_m = 20e-6;
  const std::vector<std::string> motions = {"Lz", "Ry", "M1", "Rx"};
  const gap::MeasurementData moved = Generate(reseated, IdealTracker(), motions);
  const gap::MeasurementData still = Generate({}, IdealTracker(), motions);
  ASSERT_EQ(moved.rows.size(), still.rows.size());
  std::vector<Vector3> first(motions.size(), Vector3::Constant(std::nan("")));
  double spread = 0.0;
  for (std::size_t k = 0; k < moved.rows.size(); ++k) {
    const Pose pose = Pose::FromVector(moved.rows[k].pose_cmd);
    const Vector3 in_M = RotationFromRpy(pose.rpy_rad).transpose() * (moved.rows[k].point_m - still.rows[k].point_m);
    Vector3& seat = first[static_cast<std::size_t>(moved.rows[k].run)];
    if (seat.hasNaN()) seat = in_M;
    spread = std::max(spread, (in_M - seat).norm());
  }
  EXPECT_LT(spread, 1e-8);
  for (std::size_t r = 0; r < first.size(); ++r) {
    ASSERT_FALSE(first[r].hasNaN()) << motions[r];
    EXPECT_LT(first[r].norm(), 5 * reseated.target_reseat_m) << motions[r];
    if (r == 0) continue;
    EXPECT_GT((first[r] - first[r - 1]).norm(), 1e-6) << motions[r] << " sits where " << motions[r - 1] << " did";
  }
}

TEST(BlindRig, ScenariosCoverEveryKindAndTrackerSetting) {
  std::set<std::string> kinds, truths;
  double slowest = 1e9, fastest = 0.0, quietest = 1.0, noisiest = 0.0;
  std::set<bool> encoders;
  for (int index = 0; index < 200; ++index) {
    const BlindScenario s = DrawBlindScenario(3, index);
    kinds.insert(s.kind);
    truths.insert(s.truth.begin(), s.truth.end());
    slowest = std::min(slowest, s.tracker.rate_hz), fastest = std::max(fastest, s.tracker.rate_hz);
    quietest = std::min(quietest, s.tracker.noise_m), noisiest = std::max(noisiest, s.tracker.noise_m);
    encoders.insert(s.tracker.encoders);
    EXPECT_EQ(s.truth.empty(), s.kind == "none");
  }
  EXPECT_EQ(kinds, (std::set<std::string>{"none", "single", "pair", "out_of_vocabulary"}));
  EXPECT_EQ(truths.size(), static_cast<std::size_t>(calibration::kEffectCount) + OutOfVocabularyKinds().size());
  EXPECT_LT(slowest, 20.0);
  EXPECT_GT(fastest, 500.0);
  EXPECT_LT(quietest, 4e-6);
  EXPECT_GT(noisiest, 17e-6);
  EXPECT_EQ(encoders.size(), 2u);
}

}  // namespace
}  // namespace edsp::blind
