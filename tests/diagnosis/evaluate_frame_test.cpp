// Evaluate's prediction on data that cannot fix the tracker frame's
// rotation: Rx turns the platform about point A itself (A stays where it
// is), Ly moves A along a line. The frame estimated on such data is
// arbitrary about those axes, and the prediction turned by it missed the
// measured calibrated run by 4× (Rx) and 2.4× (Ly) on the example rig. The
// fit's rotation, saved with the model, turns it instead.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/gap/closed_loop.h"
#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "offline_session.h"
#include "scratch_dir.h"
#include "platform_models.h"

namespace edsp::gap {
namespace {

// The tracker turned 0.9 rad about z from {B}: an arbitrary frame is far off.
const Pose kTrackerStand = Pose::FromVector((Vector6() << 3.2, -0.8, 0.15, 0.004, -0.006, 0.9).finished());

TEST(EvaluateFrame, APointThatStaysOrMovesOnALineDoesNotFixTheRotation) {
  const Vector3 a(1.2, 0.0, 1.5);
  EXPECT_FALSE(FixesFrameRotation(std::vector<Vector3>(50, a)));
  std::vector<Vector3> line, plane;
  for (int k = 0; k < 50; ++k) {
    line.push_back(a + Vector3(0.0, 0.01 * k, 0.0));
    plane.push_back(a + Vector3(0.01 * (k % 7), 0.01 * k, 0.0));
  }
  EXPECT_FALSE(FixesFrameRotation(line));
  EXPECT_TRUE(FixesFrameRotation(plane));
}

TEST(EvaluateFrame, ThePredictionForRxAndLyIsTurnedByTheFitsFrame) {
  const PlatformModel model(Huang2021Config());
  const RigEffects rig = test_support::OffsetsBacklashAndLead();
  const std::string dir = test_support::ScratchDir("evaluate_frame");
  const OfflineRunOptions fit =
      test_support::OfflineSession({"Lz", "Lx", "Rz", "Ry", "M1", "M2"}, 5, 0.5, 5e-6, 3, kTrackerStand, dir + "/fit");
  const Diagnosis d = Diagnose(model, LoadMeasurement(RunOffline(test_support::kShippedConfig, rig, fit).csv_path));
  const nlohmann::json saved = ModelJson(d);
  ASSERT_TRUE(saved.contains("tracker_rotation"));
  for (const char* motion : {"Rx", "Ly"}) {
    const std::string out = dir + "/" + motion;
    std::filesystem::create_directories(out);
    const MotionCheck loop = MeasureClosedLoop(model, test_support::kShippedConfig, rig, fit, saved, {motion}, out);
    ASSERT_TRUE(loop.predicted.has_value());
    EXPECT_LT(loop.after.rms_m, 0.5 * loop.before.rms_m) << motion;
    EXPECT_NEAR(loop.predicted->rms_m, loop.after.rms_m, 0.15 * loop.after.rms_m)
        << motion << ": before " << loop.before.rms_m << ", measured " << loop.after.rms_m;
  }
}

}  // namespace
}  // namespace edsp::gap
