#include "edsp/planner/calibration_motions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "edsp/kinematics/platform_loads.h"
#include "edsp/kinematics/workspace.h"

namespace edsp {

using calibration::Effect;

namespace {

// What a dwell shows: the geometry, the screws' mapping, the PR, the play
// and the static loads. Lag and heat need the motion between poses.
std::vector<Effect> StaticEffects() {
  return {Effect::kPassiveRotation,   Effect::kJointPosition, Effect::kLeadError,
          Effect::kPeriodicLeadError, Effect::kBacklash,      Effect::kCompliance};
}

Vector6 Approach(const Vector6& pose, double dz) {
  Vector6 p = pose;
  p(2) += dz;
  return p;
}

// The nominal platform with its limits drawn in by the margins.
PlatformModel WithMargins(const PlatformModel& model, const CalibrationMotionOptions& o) {
  PlatformConfig config = model.config();
  config.limits.leg_min_m += o.stroke_margin_m;
  config.limits.leg_max_m -= o.stroke_margin_m;
  config.limits.joint_angle_max_rad -= o.joint_angle_margin_rad;
  return PlatformModel(config);
}

// The largest share of the platform's weight one leg carries at the pose.
double LoadFactor(const PlatformModel& model, const Vector6& pose) {
  return LegForces(model, Pose::FromVector(pose), Vector3::Zero(), 1.0, Vector3::Zero(), Vector3(0.0, 0.0, -1.0))
      .cwiseAbs()
      .maxCoeff();
}

// What the paper's motions ask of the legs: the largest load factor at the
// single-axis extremes.
double PaperLoadFactor(const PlatformModel& model, const PaperMotionOptions& paper) {
  double worst = 0.0;
  for (int axis = 0; axis < 6; ++axis) {
    for (double side : {-1.0, 1.0}) {
      Vector6 pose = model.home_pose().ToVector();
      pose(axis) += side * (axis < 3 ? paper.linear_range_m : paper.angular_range_rad);
      if (CheckWorkspace(model, Pose::FromVector(pose)).ok()) worst = std::max(worst, LoadFactor(model, pose));
    }
  }
  return worst;
}

bool Reachable(const PlatformModel& model, const Vector6& pose, double approach_m) {
  for (double dz : {-approach_m, 0.0, approach_m}) {
    if (!CheckWorkspace(model, Pose::FromVector(Approach(pose, dz))).ok()) return false;
  }
  return true;
}

std::vector<Vector6> Candidates(const PlatformModel& model, const PaperMotionOptions& paper,
                                const CalibrationMotionOptions& o) {
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Vector6 home = model.home_pose().ToVector();
  const PlatformModel inner = WithMargins(model, o);
  const double load_max = PaperLoadFactor(model, paper);
  std::vector<Vector6> out;
  // Draws are cheap; a bounded number keeps a too-tight workspace an error.
  for (int draw = 0; draw < 50 * o.candidates && static_cast<int>(out.size()) < o.candidates; ++draw) {
    Vector6 pose = home;
    for (int axis = 0; axis < 6; ++axis) {
      pose(axis) += o.coverage * (axis < 3 ? paper.linear_range_m : paper.angular_range_rad) * unit(rng);
    }
    if (Reachable(inner, pose, o.approach_m) && LoadFactor(model, pose) <= load_max) out.push_back(pose);
  }
  return out;
}

// Information a pose adds: its dwell approached from below (play taken up
// extending) and from above (retracting).
Eigen::MatrixXd PoseInformation(const PlatformModel& model, const Vector6& q, const IdentifiabilityOptions& o) {
  IdentificationInformation info(model, StaticEffects(), o);
  calibration::LegErrorTracker tracker(model, o.errors);
  calibration::LegErrorInputs in;
  in.pose = Pose::FromVector(q);
  in.command_m = model.CompensatedLengths(in.pose, o.pr_mode);
  in.motor_m = in.command_m;
  calibration::LegErrorState state = tracker.Advance(in);
  const PointSensitivity at = PointSensitivityAt(model, in.pose);
  for (double play : {0.0, 1.0}) {
    state.play.setConstant(play);
    info.Add(at, state);
  }
  return info.Full();
}

// log det of the parameters' information once the frame is estimated:
// log det(full) − log det(frame block), with a small ridge so that the
// first poses, too few to determine everything, still rank.
double FrameFreeLogDet(const Eigen::MatrixXd& information) {
  constexpr double kRidge = 1e-3;  // (typical sizes)⁻², far below one dwell's information
  const Eigen::MatrixXd full = information + kRidge * Eigen::MatrixXd::Identity(information.rows(), information.cols());
  const Eigen::LLT<Eigen::MatrixXd> all(full), frame(full.topLeftCorner(6, 6));
  return 2.0 * (all.matrixL().toDenseMatrix().diagonal().array().log().sum() -
                frame.matrixL().toDenseMatrix().diagonal().array().log().sum());
}

// Peak leg speed per unit of 1/duration of a quintic from `from` to `to`.
double LegTravelRate(const PlatformModel& model, const Vector6& from, const Vector6& to) {
  const Vector6 delta = to - from;
  double peak = 0.0;
  constexpr int kPoints = 32;
  for (int k = 1; k < kPoints; ++k) {
    const double s = static_cast<double>(k) / kPoints;
    const double shape = 10.0 * s * s * s - 15.0 * s * s * s * s + 6.0 * s * s * s * s * s;
    const double rate = 30.0 * s * s * (1.0 - s) * (1.0 - s);
    const Matrix6 M = model.LengthJacobian(Pose::FromVector(from + shape * delta));
    peak = std::max(peak, (M * delta).cwiseAbs().maxCoeff() * rate);
  }
  return peak;
}

// A straight move in pose space between two reachable poses can still pass
// outside the workspace (a corner of the rotations).
bool PathReachable(const PlatformModel& model, const Vector6& from, const Vector6& to) {
  constexpr int kPoints = 50;
  for (int k = 1; k < kPoints; ++k) {
    const double s = static_cast<double>(k) / kPoints;
    if (!CheckWorkspace(model, Pose::FromVector(from + s * (to - from))).ok()) return false;
  }
  return true;
}

// Nearest-neighbour tour from home (metres and radians weighted alike:
// the platform's joints sit about a metre from its centre).
std::vector<Vector6> Tour(std::vector<Vector6> poses, const Vector6& home) {
  std::vector<Vector6> out;
  Vector6 at = home;
  while (!poses.empty()) {
    auto next = std::min_element(poses.begin(), poses.end(),
                                 [&](const Vector6& a, const Vector6& b) { return (a - at).norm() < (b - at).norm(); });
    at = *next;
    out.push_back(at);
    poses.erase(next);
  }
  return out;
}

}  // namespace

QuinticMove QuinticAtLegSpeed(const PlatformModel& model, const Vector6& from, const Vector6& to, double leg_speed_m_s,
                              double min_duration_s) {
  if (!(leg_speed_m_s > 0.0)) throw std::invalid_argument("leg speed must be positive");
  return QuinticMove(from, to, std::max(min_duration_s, LegTravelRate(model, from, to) / leg_speed_m_s));
}

double StaticDesignCriterion(const PlatformModel& model, const std::vector<Vector6>& poses,
                             const IdentifiabilityOptions& options) {
  Eigen::MatrixXd information;
  for (const Vector6& q : poses) {
    const Eigen::MatrixXd gain = PoseInformation(model, q, options);
    information = information.size() == 0 ? gain : Eigen::MatrixXd(information + gain);
  }
  return FrameFreeLogDet(information);
}

std::vector<Vector6> SelectCalibrationPoses(const PlatformModel& model, const PaperMotionOptions& paper,
                                            const CalibrationMotionOptions& o) {
  if (o.poses < 1 || o.blocks < 1 || o.poses < o.blocks) {
    throw std::invalid_argument(fmt::format("calibration motions: {} poses in {} blocks", o.poses, o.blocks));
  }
  const std::vector<Vector6> candidates = Candidates(model, paper, o);
  if (static_cast<int>(candidates.size()) < o.poses) {
    throw std::invalid_argument(fmt::format(
        "calibration motions: only {} reachable candidate poses within {:.0f}% of the ranges (and within the "
        "legs' loads at the paper's extremes), {} needed",
        candidates.size(), 100.0 * o.coverage, o.poses));
  }
  std::vector<Eigen::MatrixXd> gain;
  for (const Vector6& q : candidates) gain.push_back(PoseInformation(model, q, o.identifiability));
  Eigen::MatrixXd information = Eigen::MatrixXd::Zero(gain[0].rows(), gain[0].cols());
  std::vector<bool> taken(candidates.size(), false);
  std::vector<Vector6> selected;
  while (static_cast<int>(selected.size()) < o.poses) {
    std::size_t best = 0;
    double best_value = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      if (taken[k]) continue;
      const double value = FrameFreeLogDet(information + gain[k]);
      if (value > best_value) best_value = value, best = k;
    }
    taken[best] = true;
    information += gain[best];
    selected.push_back(candidates[best]);
  }
  return selected;
}

void AppendCalibrationMotions(const PlatformModel& model, const PaperMotionOptions& paper,
                              const CalibrationMotionOptions& o, TrajectorySequence* sequence) {
  if (o.leg_speed_levels.empty()) throw std::invalid_argument("calibration motions: no leg speed levels");
  const std::vector<Vector6> selected = SelectCalibrationPoses(model, paper, o);
  const Vector6 home = model.home_pose().ToVector();
  const PlatformModel inner = WithMargins(model, o);
  const double speed_max = model.config().limits.leg_speed_max_m_s;
  Vector6 at = sequence->size() == 0 ? home : sequence->EndPose();
  int move = 0;
  for (int b = 0; b < o.blocks; ++b) {
    const std::string run = fmt::format("cal{}", b + 1);
    auto go = [&](const Vector6& to, const std::string& label, double level) {
      if ((to - at).cwiseAbs().maxCoeff() > 0.0) {
        sequence->Append(fmt::format("{}/move {}", run, label), std::make_unique<QuinticMove>(QuinticAtLegSpeed(
                                                                    model, at, to, level * speed_max, o.min_move_s)));
      }
      at = to;
    };
    auto dwell = [&](const std::string& label) {
      sequence->Append(fmt::format("{}/dwell {}", run, label), std::make_unique<Dwell>(at, paper.dwell_s));
    };
    go(home, "home", o.leg_speed_levels.back());
    dwell("start");
    std::vector<Vector6> mine;
    for (std::size_t k = static_cast<std::size_t>(b); k < selected.size(); k += static_cast<std::size_t>(o.blocks)) {
      mine.push_back(selected[k]);
    }
    const double slow = o.leg_speed_levels.front();
    int index = 0;
    for (const Vector6& pose : Tour(mine, home)) {
      const std::string label = std::to_string(++index);
      // The speed sweep: each move between poses at the next level.
      const double level = o.leg_speed_levels[static_cast<std::size_t>(move++) % o.leg_speed_levels.size()];
      const Vector6 below = Approach(pose, -o.approach_m);
      if (!PathReachable(inner, at, below)) go(home, label + " via home", level);
      go(below, label, level);
      go(pose, label + "+", slow);
      dwell(label + "+");
      go(Approach(pose, o.approach_m), label + " over", slow);
      go(pose, label + "-", slow);
      dwell(label + "-");
    }
    go(home, "home", o.leg_speed_levels.back());
    dwell("home");
  }
}

}  // namespace edsp
