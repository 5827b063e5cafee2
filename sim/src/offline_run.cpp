#include "edsp/sim/offline_run.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

#include "edsp/channels.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/kinematics_node.h"
#include "edsp/logger/measurement_export.h"
#include "edsp/planner/motion_library.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/sim/stack_simulation.h"

namespace edsp {

namespace {

// Writes edsp messages to a standard LCM log, stamped with simulated time.
class SimLog {
 public:
  explicit SimLog(const std::string& path) : path_(path), file_(path, "w") {
    if (!file_.good()) throw std::runtime_error(path + ": cannot create log file");
  }
  template <typename Msg>
  void Write(const char* channel, const Msg& msg, std::int64_t utime) {
    buffer_.resize(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
    lcm::LogEvent e{};
    e.eventnum = events_++;
    e.timestamp = utime;
    e.channel = channel;
    e.datalen = static_cast<std::int32_t>(buffer_.size());
    e.data = buffer_.data();
    if (file_.writeEvent(&e) != 0) throw std::runtime_error(path_ + ": write failed (disk full?)");
  }

 private:
  std::string path_;
  lcm::LogFile file_;
  std::vector<std::uint8_t> buffer_;
  std::int64_t events_ = 0;
};

// With a calibration, the rig's unrecorded hold at home before the motions.
constexpr const char* kSettleSegment = "settle under the calibration";
constexpr double kCalibrationSettle_s = 0.5;

}  // namespace

OfflineRunResult RunOffline(const std::string& config_path, const OfflineRunOptions& options) {
  return RunOffline(config_path, LoadRigEffects(config_path), options);
}

OfflineRunResult RunOffline(const std::string& config_path, const RigEffects& effects,
                            const OfflineRunOptions& options) {
  const std::string config_text = ReadConfigText(config_path);
  const PlatformConfig nominal = ParseConfig(config_text, config_path);
  RigParameters rig = IdealRig(nominal);
  rig.effects = effects;
  rig.tracker = options.tracker;
  StackOptions stack;
  stack.pr_mode = options.pr_mode;
  stack.rig = rig;
  const PlatformModel model(nominal);
  const std::string calibration_path =
      options.calibration_path.empty() ? LoadConfigFile(config_path).calibration_model : options.calibration_path;
  if (!calibration_path.empty()) {
    stack.calibration = calibration::LoadCalibration(calibration_path, model,
                                                     options.apply_ambiguous || nominal.calibration_apply_ambiguous);
  }
  // The same motions as the live planner plans for this platform, whatever
  // the compensation this run applies. With a calibration the rig first
  // settles at home under it, unrecorded, as a rig team applies one and
  // then measures: its first correction is not a transient of the run.
  std::unique_ptr<TrajectorySequence> motions = std::make_unique<TrajectorySequence>();
  const int settle_segments = stack.calibration ? 1 : 0;  // the first segments, left out of the log
  if (stack.calibration) {
    motions->Append(kSettleSegment, std::make_unique<Dwell>(model.home_pose().ToVector(), kCalibrationSettle_s));
  }
  for (const std::string& name : options.motions) AppendMotion(model, name, options.paper, motions.get());
  StackSimulation sim(nominal, std::move(motions), stack);

  std::error_code ec;
  std::filesystem::create_directories(options.out_dir, ec);
  if (ec) throw std::runtime_error(options.out_dir + ": cannot create directory (" + ec.message() + ")");
  OfflineRunResult result;
  if (stack.calibration) result.calibration = stack.calibration->Describe();
  result.log_path = (std::filesystem::path(options.out_dir) / "run.lcmlog").string();
  result.csv_path = (std::filesystem::path(options.out_dir) / "measurement.csv").string();
  {
    SimLog log(result.log_path);
    KinematicsNodeOptions config_options;
    config_options.session_id = stack.session_id;
    config_options.calibration = stack.calibration;       // named on EDSP_CONFIG, as live
    KinematicsNode config_source(model, config_options);  // the same latched config message
    std::int64_t utime = stack.start_utime;
    log.Write(channel::kConfig, config_source.ConfigMessage(utime, config_text), utime);
    std::size_t faults_seen = 0;
    // A step commands time t and leaves the rig (truth, tracker) at t + 1 ms,
    // the time of the next setpoint: they are logged after it, so each
    // tracker row of the measurement CSV sits beside the setpoint and command
    // of its own instant, as a live tracker's timestamps would put it.
    StackSample previous;
    bool have_previous = false;
    double sum_sq = 0.0;
    auto write_rig = [&](const StackSample& s, const pose_setpoint_t& now) {
      log.Write(channel::kRigTruth, s.truth, s.truth.utime);
      if (!s.tracker_due) return;
      log.Write(channel::kTracker, s.tracker, s.tracker.utime);
      ++result.tracker_samples;
      Vector6 q;
      for (int k = 0; k < 6; ++k) q(k) = now.pose[k];
      const Vector3 target = PointInBase(options.tracker.X_TB, model.ObservationPoint(Pose::FromVector(q)));
      const double e = (Vector3(s.tracker.point_m[0], s.tracker.point_m[1], s.tracker.point_m[2]) - target).norm();
      result.max_error_m = std::max(result.max_error_m, e);
      sum_sq += e * e;
    };
    while (!sim.Finished()) {
      const StackSample s = sim.Step();
      if (s.setpoint.segment < settle_segments) continue;
      utime = s.setpoint.utime;
      log.Write(channel::kSetpoint, s.setpoint, utime);
      if (s.command_valid) log.Write(channel::kLegCommand, s.command, utime);
      log.Write(channel::kLegState, s.legs, utime);
      if (have_previous) write_rig(previous, s.setpoint);
      for (; faults_seen < sim.faults().size(); ++faults_seen)
        log.Write(channel::kFault, sim.faults()[faults_seen], utime);
      previous = s;
      have_previous = true;
      ++result.cycles;
    }
    result.faults = static_cast<std::int64_t>(sim.faults().size());
    if (result.tracker_samples > 0)
      result.rms_error_m = std::sqrt(sum_sq / static_cast<double>(result.tracker_samples));
    result.duration_s = static_cast<double>(result.cycles) * stack.cycle_s;
  }
  std::ofstream csv(result.csv_path);
  if (!csv) throw std::runtime_error(result.csv_path + ": cannot create file");
  ExportMeasurementCsv(result.log_path, csv);
  csv.close();
  if (!csv) throw std::runtime_error(result.csv_path + ": write failed (disk full?)");
  return result;
}

std::vector<EffectError> PerEffectErrors(const std::string& config_path, const OfflineRunOptions& options) {
  const RigEffects all = LoadRigEffects(config_path);
  std::vector<EffectError> table;
  for (const calibration::Effect effect : EnabledEffects(all)) {
    const std::string name = calibration::EffectName(effect);
    OfflineRunOptions o = options;
    o.out_dir = (std::filesystem::path(options.out_dir) / name).string();
    const OfflineRunResult r = RunOffline(config_path, OnlyEffect(all, effect), o);
    table.push_back({name, r.max_error_m, r.rms_error_m});
  }
  return table;
}

}  // namespace edsp
