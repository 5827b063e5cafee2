// The blind rig without effects is the nominal platform (checked against
// edsp's own kinematics), each effect leaves its signature, and the drawn
// scenarios cover the kinds and tracker settings they promise.
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

TEST(BlindRig, ScenariosCoverEveryKindAndTrackerSetting) {
  std::set<std::string> kinds, truths;
  double slowest = 1e9, fastest = 0.0, quietest = 1.0, noisiest = 0.0;
  std::set<bool> encoders;
  for (int index = 0; index < 100; ++index) {
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
