#include "score_command.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/channels.h"
#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/live_score.h"
#include "edsp/cueing/vehicle_message.h"
#include "edsp/logger/logged_message.h"
#include "edsp/platform_state_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "edsp/vehicle_motion_t.hpp"
#include "perception_json.h"

namespace edsp {
namespace {

struct LoggedCueing {
  std::optional<std::int64_t> session;  // the cueing setpoints'
  std::vector<StampedPose> commanded;   // the longest stretch of them
  std::vector<HeardVehicleSample> vehicle;
  std::size_t vehicle_refused = 0;  // of the session, that the cueing refused too
  std::vector<StampedPose> truth, encoders;
};

Vector6 PoseOf(const double (&pose)[6]) { return Eigen::Map<const Vector6>(pose); }

void TakeSetpoint(const pose_setpoint_t& s, std::vector<StampedPose>& stretch, LoggedCueing& log) {
  if (s.phase != pose_setpoint_t::PHASE_CUEING) {
    if (stretch.size() > log.commanded.size()) log.commanded.swap(stretch);
    stretch.clear();
    return;
  }
  if (!log.session) log.session = s.session_id;
  if (s.session_id == *log.session) stretch.push_back({s.utime, PoseOf(s.pose)});
}

LoggedCueing ReadLog(const std::string& path, double input_timeout_s) {
  LoggedCueing log;
  std::vector<StampedPose> stretch;
  std::vector<std::pair<std::int64_t, vehicle_motion_t>> heard;  // sessions judged once the setpoints named theirs
  LogReader reader(path);
  LogEvent event;
  while (reader.Next(&event)) {
    if (pose_setpoint_t s; event.channel == channel::kSetpoint && DecodeEvent(event, &s)) {
      TakeSetpoint(s, stretch, log);
    } else if (vehicle_motion_t v; event.channel == channel::kVehicle && DecodeEvent(event, &v)) {
      heard.emplace_back(event.timestamp_utime, v);
    } else if (rig_truth_t t; event.channel == channel::kRigTruth && DecodeEvent(event, &t)) {
      log.truth.push_back({t.utime, PoseOf(t.pose)});
    } else if (platform_state_t p; event.channel == channel::kPlatformState && DecodeEvent(event, &p)) {
      log.encoders.push_back({p.utime, PoseOf(p.pose)});
    }
  }
  if (stretch.size() > log.commanded.size()) log.commanded.swap(stretch);
  // What the cueing itself took (VehicleInput): a sample it refused (a
  // number no vehicle makes, a sequence not ahead of the last) is not what
  // the rider should feel; after a silence it took for a lost input, a new
  // stream starts.
  bool streaming = false;  // a sample taken, no silence since
  std::uint32_t last_sequence = 0;
  std::int64_t last_utime = 0;
  for (const auto& [utime, v] : heard) {
    if (!log.session || v.session_id != *log.session) continue;
    if (utime - last_utime > std::llround(input_timeout_s * 1e6)) streaming = false;
    const ParsedVehiclePacket read = ReadVehicleMessage(v);
    const bool ahead = read.packet && (!streaming || SequenceIsAhead(read.packet->sequence, last_sequence));
    if (!ahead) {
      ++log.vehicle_refused;
      continue;
    }
    streaming = true;
    last_sequence = read.packet->sequence;
    last_utime = utime;
    log.vehicle.push_back({utime, read.packet->specific_force_m_s2, read.packet->angular_velocity_rad_s});
  }
  return log;
}

nlohmann::json ScoreJson(const PerceptionScore& score) {
  return {{"perception_error", score.overall}, {"channels", ChannelsJson(score)}};
}

void PrintScoreRow(const char* name, const PerceptionScore& score) {
  std::string channels;
  for (const ChannelScore& c : score.channels) channels += fmt::format(" {:6.2f}", c.in_thresholds);
  std::printf("%-10s %6.2f %s   %5.1f ms\n", name, score.overall, channels.c_str(), score.channels[0].delay_s * 1e3);
}

}  // namespace

int RunScore(const ScoreOptions& options) {
  const CueingConfig config = LoadCueingConfig(options.cueing_path);
  const LoggedCueing log = ReadLog(options.log_path, config.input.timeout_s);
  if (log.commanded.empty()) {
    throw std::runtime_error(
        fmt::format("{}: no setpoint of a cueing (EDSP_SETPOINT, trajectory \"cueing\")", options.log_path));
  }
  if (log.vehicle.empty()) {
    throw std::runtime_error(fmt::format(
        "{}: no vehicle sample of session {} on {}: the cueing took none, or the logger did not record the channel",
        options.log_path, *log.session, channel::kVehicle));
  }
  const bool from_truth = !log.truth.empty();
  const char* real_from = from_truth ? channel::kRigTruth : channel::kPlatformState;
  LiveCueingScore score;
  try {
    score = ScoreLiveCueing(config, log.vehicle, log.commanded, from_truth ? log.truth : log.encoders);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: {}", options.log_path, e.what()));
  }
  if (options.json) {
    const nlohmann::json out = {{"log", options.log_path},
                                {"session_id", *log.session},
                                {"start_utime", score.start_utime},
                                {"duration_s", score.duration_s},
                                {"vehicle_samples", log.vehicle.size()},
                                {"vehicle_samples_refused", log.vehicle_refused},
                                {"real_from", score.real ? nlohmann::json(real_from) : nlohmann::json(nullptr)},
                                {"commanded", ScoreJson(score.commanded)},
                                {"real", score.real ? ScoreJson(*score.real) : nlohmann::json(nullptr)}};
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("%s: %.3f s of cueing, session %lld, %zu vehicle samples (%zu refused); real motion from %s\n",
              options.log_path.c_str(), score.duration_s, static_cast<long long>(*log.session), log.vehicle.size(),
              log.vehicle_refused, score.real ? real_from : "(none spanning the run)");
  std::printf("perceived error in thresholds (overall, then fx fy fz wx wy wz), fx's delay\n");
  PrintScoreRow("commanded", score.commanded);
  if (score.real) PrintScoreRow("real", *score.real);
  return 0;
}

}  // namespace edsp
