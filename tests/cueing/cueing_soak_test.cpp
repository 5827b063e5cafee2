// The soak's random vehicle and its count of refused setpoints, the first
// refusal against the kinematics' own whole-path check on the same path.
#include "edsp/cueing/cueing_soak.h"

#include <cmath>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "edsp/cueing/classical_washout.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/path_check.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

TEST(RandomVehicle, EachChannelHasItsRmsAndASeedRepeatsIt) {
  const RandomVehicleParameters parameters;
  RandomVehicle a(parameters, 1e-3, 7), b(parameters, 1e-3, 7), c(parameters, 1e-3, 8);
  double sum[kCueChannels] = {};
  bool differs = false;
  const int n = 1'000'000;
  for (int k = 0; k < n; ++k) {
    const VehicleSample sa = a.Next(), sb = b.Next(), sc = c.Next();
    ASSERT_EQ(sa.specific_force_m_s2, sb.specific_force_m_s2);
    differs = differs || sa.angular_velocity_rad_s != sc.angular_velocity_rad_s;
    for (int channel = 0; channel < kCueChannels; ++channel) {
      const double v = ChannelValue(sa, channel) - (channel == 2 ? kStandardGravity_m_s2 : 0.0);
      sum[channel] += v * v;
    }
  }
  EXPECT_TRUE(differs);
  for (int channel = 0; channel < kCueChannels; ++channel) {
    const double rms = std::sqrt(sum[channel] / n);
    const double want =
        channel < 3 ? parameters.force_rms_m_s2(channel) : parameters.angular_velocity_rms_rad_s(channel - 3);
    EXPECT_NEAR(rms, want, 0.05 * want) << CueChannelName(channel);
  }
}

struct Soak : testing::Test {
  PlatformModel model{LoadConfigFile(SourceDir() + "/config/huang2021.toml")};
  CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
};

TEST_F(Soak, AGentleRideIsNeverRefused) {
  RandomVehicleParameters gentle;
  gentle.force_rms_m_s2 = Vector3::Constant(0.2);
  gentle.angular_velocity_rms_rad_s = Vector3::Constant(0.02);
  const CueingSoak soak = SoakCueing(model, config, CueingAlgorithm::kClassicalWashout, gentle, 100'000, 3);
  EXPECT_EQ(soak.refused_setpoints, 0) << soak.first_refusal;
  EXPECT_GT(soak.peak_stroke_used, 0.0);
  EXPECT_GT(soak.step_p99_us, 0.0);
}

TEST_F(Soak, ARoughRideIsRefusedWhereTheWholePathCheckRefusesIt) {
  const RandomVehicleParameters rough;
  const CueingSoak soak = SoakCueing(model, config, CueingAlgorithm::kClassicalWashout, rough, 20'000, 5);
  ASSERT_GT(soak.refused_setpoints, 0);
  // The same ride again, its path judged by the kinematics' whole-path check.
  ClassicalWashout washout(config.washout, 1e-3);
  RandomVehicle vehicle(rough, 1e-3, 5);
  std::vector<Pose> poses;
  for (int k = 0; k < 20'000; ++k) {
    poses.push_back(CueToPlatformPose(model.home_pose(), config.head_in_platform_m, washout.Step(vehicle.Next())));
  }
  const PathCheck check = CheckPath(
      model, PathLimitsOf(model),
      [&](double t) {
        return poses[std::min(poses.size() - 1, static_cast<std::size_t>(std::llround(t * 1e3)))].ToVector();
      },
      static_cast<double>(poses.size() - 1) * 1e-3);
  ASSERT_FALSE(check.ok());
  EXPECT_EQ(soak.first_refusal.rfind(fmt::format("at cycle {}:", std::llround(check.t_s * 1e3)), 0), 0u)
      << soak.first_refusal << " | " << check.Describe();
}

}  // namespace
}  // namespace edsp
