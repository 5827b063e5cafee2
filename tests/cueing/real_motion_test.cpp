// Cueing scored on the platform's real motion: the setpoints played through
// the offline stack and rig. An ideal drive lands every setpoint one cycle
// later; a slow drive loop is felt as the delay it adds.
#include <cmath>

#include <gtest/gtest.h>

#include "edsp/cueing/cueing_run.h"
#include "edsp/cueing/platform_motion.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/build_paths.h"
#include "edsp/sim/played_poses.h"

namespace edsp {
namespace {

struct LaneChange {
  PlatformConfig nominal = LoadConfigFile(SourceDir() + "/config/huang2021.toml");
  CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  CueingRun run = RunCueing(PlatformModel(nominal), config, CueingAlgorithm::kClassicalWashout,
                            LoadManoeuvre(SourceDir() + "/config/manoeuvres/lane_change.toml"));
};

PerceptionScore ScoreOn(const LaneChange& c, const std::vector<Pose>& truth) {
  const double period = 1.0 / c.config.rate_hz;
  return ScorePerception(c.config.perception, c.run.vehicle,
                         PlatformMotionAtHead(truth, period, c.config.head_in_platform_m));
}

TEST(RealMotion, AnIdealDriveIsWhereEverySetpointSays) {
  const LaneChange c;
  RigEffects ideal;
  ideal.servo_lag.enabled = false;
  const std::vector<Pose> truth = PlayPosesThroughTheStack(c.nominal, ideal, c.run.commanded, 1e-3);
  ASSERT_EQ(truth.size(), c.run.commanded.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    worst = std::max(worst, (truth[k].p_BoMo_B - c.run.commanded[k].p_BoMo_B).norm());
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(ScoreOn(c, truth).overall, c.run.score.overall, 1e-3 * c.run.score.overall);
}

TEST(RealMotion, ASlowLoadedDriveLoopIsFeltAsTheDelayItAdds) {
  const LaneChange c;
  RigEffects slow;
  // A position loop of 2 Hz whose motors carry 2 t, which the bridge's
  // feed-forward does not know: it lags like a first-order loop, about
  // 1/(2π·2 Hz) = 80 ms. (At the shipped 50 Hz and no load the
  // feed-forward leaves no delay a rider could feel: 1 ms at most.)
  slow.servo_lag.bandwidth_hz = 2.0;
  slow.servo_lag.load_mass_kg = 2000.0;
  const double expected_lag_s = 1.0 / (2.0 * kPi * slow.servo_lag.bandwidth_hz);
  const std::vector<Pose> truth = PlayPosesThroughTheStack(c.nominal, slow, c.run.commanded, 1e-3);
  const double period = 1.0 / c.config.rate_hz;
  // The rider on the real platform against the rider on the commanded one.
  const PerceptionScore lag = ScorePerception(c.config.perception, c.run.platform,
                                              PlatformMotionAtHead(truth, period, c.config.head_in_platform_m));
  EXPECT_GT(lag.channels[1].correlation, 0.9);
  EXPECT_GT(lag.channels[1].delay_s, 0.5 * expected_lag_s);
  EXPECT_LT(lag.channels[1].delay_s, 1.5 * expected_lag_s);
  EXPECT_GT(ScoreOn(c, truth).channels[1].rms_error, c.run.score.channels[1].rms_error);
}

TEST(RealMotion, APathAtAnotherRateThanTheStacksIsRefused) {
  const LaneChange c;
  EXPECT_THROW(PlayPosesThroughTheStack(c.nominal, RigEffects{}, c.run.commanded, 2e-3), std::invalid_argument);
}

}  // namespace
}  // namespace edsp
