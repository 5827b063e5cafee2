// The model-predictive cueing: its box keeps every leg inside its limits
// (checked on poses, speeds and accelerations drawn inside it, by the legs'
// own lengths), a rough ride never leaves a limit, it cues the manoeuvres
// better than classical washout, and a lost input washes out to neutral.
#include "edsp/cueing/mpc_cueing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "edsp/config_file/config_error.h"
#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/cueing_run.h"
#include "edsp/cueing/cueing_soak.h"
#include "edsp/cueing/manoeuvre.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

struct Mpc : testing::Test {
  PlatformModel model{LoadConfigFile(SourceDir() + "/config/huang2021.toml")};
  CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  double period = 1.0 / config.rate_hz;
};

Vector6 Draw(std::mt19937_64& random, const Vector6& half) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Vector6 q;
  for (int j = 0; j < 6; ++j) q(j) = unit(random) * half(j);
  return q;
}

// Poses, velocities and accelerations drawn anywhere in the box, their
// legs' lengths, speeds and accelerations by finite differences of the
// lengths along a path through the draw: never past a limit.
TEST_F(Mpc, AnyPointOfTheBoxKeepsEveryLegInsideItsLimits) {
  const MpcAxisLimits box = DeriveMpcLimits(model, model.home_pose(), config.mpc.wanted, config.mpc.leg_margin);
  EXPECT_GT(box.position.minCoeff(), 0.0) << box.Describe();
  const WorkspaceLimits& legs = model.config().limits;
  const double accel_max = model.config().motion.leg_accel_max_m_s2;
  std::mt19937_64 random(20261207);
  const double dt = 1e-4;
  double worst_stroke = -1e9, worst_speed = -1e9, worst_accel = -1e9;  // the largest excess over a limit
  for (int k = 0; k < 20'000; ++k) {
    const Vector6 q = Draw(random, box.position), v = Draw(random, box.velocity), a = Draw(random, box.acceleration);
    const auto at = [&](double t) {
      return model.LegLengths(Pose::FromVector(model.home_pose().ToVector() + q + v * t + 0.5 * a * t * t));
    };
    const Vector6 l0 = at(0.0), lp = at(dt), lm = at(-dt);
    worst_stroke = std::max({worst_stroke, legs.leg_min_m - l0.minCoeff(), l0.maxCoeff() - legs.leg_max_m});
    worst_speed = std::max(worst_speed, ((lp - lm) / (2 * dt)).cwiseAbs().maxCoeff() - legs.leg_speed_max_m_s);
    worst_accel = std::max(worst_accel, ((lp - 2 * l0 + lm) / (dt * dt)).cwiseAbs().maxCoeff() - accel_max);
  }
  EXPECT_LT(worst_stroke, 0.0) << box.Describe();
  EXPECT_LT(worst_speed, 0.0) << box.Describe();
  EXPECT_LT(worst_accel, 0.0) << box.Describe();
}

// 10⁵ cycles of the bench's rough ride, every setpoint judged as the
// kinematics and the bridge would (the bench runs 10⁶): classical washout
// is refused on the same ride.
TEST_F(Mpc, ARoughRideNeverLeavesALimit) {
  const RandomVehicleParameters rough;
  const CueingSoak mpc = SoakCueing(model, config, CueingAlgorithm::kModelPredictive, rough, 100'000, 11);
  EXPECT_EQ(mpc.refused_setpoints, 0) << mpc.first_refusal;
  EXPECT_GT(mpc.peak_stroke_used, 0.2) << "the ride used the platform";
  const CueingSoak washout = SoakCueing(model, config, CueingAlgorithm::kClassicalWashout, rough, 100'000, 11);
  EXPECT_GT(washout.refused_setpoints, 0) << "the ride is rough enough to test anything";
}

// Perception error over every manoeuvre of the repo, commanded motion:
// the model-predictive cueing feels closer than classical washout on
// average (docs/cueing.md gives the figure and why it is not the 0.7
// aimed at), on every manoeuvre with a sustained cue (the tilt it plans), and no
// manoeuvre leaves a limit.
TEST_F(Mpc, TheManoeuvresAreFeltCloserThanClassicalWashoutFeelsThem) {
  double mpc_sum = 0.0, washout_sum = 0.0;
  int count = 0;
  for (const char* name :
       {"banked_curve", "braking", "coordinated_turn", "lane_change", "slalom", "take_off_roll", "turbulence"}) {
    const Manoeuvre m = LoadManoeuvre(SourceDir() + "/config/manoeuvres/" + name + ".toml");
    const CueingRun mpc = RunCueing(model, config, CueingAlgorithm::kModelPredictive, m);
    const CueingRun washout = RunCueing(model, config, CueingAlgorithm::kClassicalWashout, m);
    EXPECT_TRUE(mpc.path.ok()) << name << ": " << mpc.path.Describe();
    const std::string sustained = name;
    if (sustained == "braking" || sustained == "take_off_roll" || sustained == "banked_curve") {
      EXPECT_LT(mpc.score.overall, 0.8 * washout.score.overall) << name;
    }
    mpc_sum += mpc.score.overall;
    washout_sum += washout.score.overall;
    ++count;
    std::printf("%-18s mpc %6.3f  washout %6.3f\n", name, mpc.score.overall, washout.score.overall);
  }
  EXPECT_LE(mpc_sum / count, 0.85 * washout_sum / count) << mpc_sum / count << " against " << washout_sum / count;
}

// The vehicle at rest after a brake (an input lost fades to rest): the
// platform comes back to neutral and stays there, slowly enough that the
// otoliths, which still feel the brake's tilt fade for seconds (τL 5.3 s),
// perceive no false cue on the way: within a minute.
TEST_F(Mpc, ARiderAtRestAfterABrakeIsWashedBackToNeutral) {
  MpcCueing mpc(model, model.home_pose(), config.head_in_platform_m, config.perception, config.mpc, period);
  const VehicleSeries brake = SampleManoeuvre(LoadManoeuvre(SourceDir() + "/config/manoeuvres/braking.toml"), period);
  double peak = 0.0;
  for (const VehicleSample& s : brake.samples) {
    mpc.Step(s);
    peak = std::max(peak, mpc.displacement().cwiseAbs().maxCoeff());
  }
  EXPECT_GT(peak, 0.05) << "the brake tilted the platform";
  const VehicleSample rest;
  double last_peak = 0.0;
  for (int k = 0; k < 60'000; ++k) {
    mpc.Step(rest);
    if (k >= 50'000) last_peak = std::max(last_peak, mpc.displacement().cwiseAbs().maxCoeff());
  }
  EXPECT_LT(last_peak, 1e-3) << "the last 10 s of a minute at rest: " << mpc.displacement().transpose();
}

TEST(MpcConfig, AnAlgorithmOfAnotherNameIsRefusedNamingIt) {
  EXPECT_EQ(ParseCueingConfig("[cueing]\nalgorithm = \"mpc\"\n", "cueing.toml").algorithm,
            CueingAlgorithm::kModelPredictive);
  try {
    ParseCueingConfig("[cueing]\nalgorithm = \"mcp\"\n", "cueing.toml");
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cueing.toml:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"mcp\""), std::string::npos) << e.what();
  }
}

TEST(MpcConfig, AnAbsurdValueIsNamedWithItsKeyAndLine) {
  const std::string base = "[cueing]\n[input]\n[washout]\n[perception]\n[mpc]\n";
  for (const auto& [line, key] :
       std::vector<std::pair<std::string, std::string>>{{"jerk_max = [40, 40, -1, 40, 40, 40]", "jerk_max"},
                                                        {"position_max = [0.1, 0.1, 0.1]", "position_max"},
                                                        {"leg_margin = 0.9", "leg_margin"},
                                                        {"fine_intervals = 0", "fine_intervals"},
                                                        {"jerk_penalty = -1", "jerk_penalty"},
                                                        {"horizon_s = 1", "horizon_s"}}) {
    try {
      ParseCueingConfig(base + line + "\n", "cueing.toml");
      ADD_FAILURE() << line << ": accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("cueing.toml:6"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace edsp
