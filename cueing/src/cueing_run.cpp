#include "edsp/cueing/cueing_run.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "edsp/cueing/platform_motion.h"

namespace edsp {
namespace {

double PeakStrokeUsed(const PlatformModel& model, const std::vector<Pose>& poses) {
  const WorkspaceLimits& limits = model.config().limits;
  const Vector6& home = model.home_length_m();
  double peak = 0.0;
  for (const Pose& pose : poses) {
    const Vector6 length = model.LegLengths(pose);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const double room = std::min(home(leg) - limits.leg_min_m, limits.leg_max_m - home(leg));
      peak = std::max(peak, std::fabs(length(leg) - home(leg)) / room);
    }
  }
  return peak;
}

}  // namespace

CueingRun RunCueing(const PlatformModel& model, const CueingConfig& config, CueingAlgorithm algorithm,
                    const Manoeuvre& manoeuvre) {
  const double period_s = 1.0 / config.rate_hz;
  CueingRun run;
  run.vehicle = SampleManoeuvre(manoeuvre, period_s);
  const std::unique_ptr<CueingFilter> filter = MakeCueingFilter(algorithm, model, config);
  run.commanded.reserve(run.vehicle.samples.size());
  for (const VehicleSample& sample : run.vehicle.samples) {
    run.commanded.push_back(CueToPlatformPose(model.home_pose(), config.head_in_platform_m, filter->Step(sample)));
  }
  const auto& poses = run.commanded;
  run.path = CheckPath(
      model, PathLimitsOf(model),
      [&poses, period_s](double t_s) {
        const auto k = std::min(poses.size() - 1, static_cast<std::size_t>(std::llround(t_s / period_s)));
        return poses[k].ToVector();
      },
      static_cast<double>(poses.size() - 1) * period_s, config.rate_hz);
  run.peak_stroke_used = PeakStrokeUsed(model, poses);
  run.platform = PlatformMotionAtHead(poses, period_s, config.head_in_platform_m);
  run.score = ScorePerception(config.perception, run.vehicle, run.platform);
  return run;
}

std::string CueingRunCsv(const CueingRun& run) {
  std::string csv =
      "t_s,vehicle_fx,vehicle_fy,vehicle_fz,vehicle_wx,vehicle_wy,vehicle_wz,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad,"
      "platform_fx,platform_fy,platform_fz,platform_wx,platform_wy,platform_wz\n";
  for (std::size_t k = 0; k < run.vehicle.samples.size(); ++k) {
    const VehicleSample& v = run.vehicle.samples[k];
    const VehicleSample& p = run.platform.samples[k];
    const Vector6 q = run.commanded[k].ToVector();
    csv += fmt::format("{:.4f}", v.t_s);
    for (int channel = 0; channel < kCueChannels; ++channel) csv += fmt::format(",{:.6g}", ChannelValue(v, channel));
    for (int i = 0; i < 6; ++i) csv += fmt::format(",{:.9g}", q(i));
    for (int channel = 0; channel < kCueChannels; ++channel) csv += fmt::format(",{:.6g}", ChannelValue(p, channel));
    csv += "\n";
  }
  return csv;
}

}  // namespace edsp
