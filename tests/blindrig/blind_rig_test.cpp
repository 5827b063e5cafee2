// The blind rig without effects is the nominal platform (checked against
// edsp's own kinematics), each effect leaves its signature, and the drawn
// scenarios cover the kinds and tracker settings they promise.
#include <cmath>
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
