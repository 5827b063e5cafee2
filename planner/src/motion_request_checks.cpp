#include "edsp/planner/motion_request_checks.h"

#include <cmath>

#include <fmt/format.h>

#include "edsp/kinematics/pose.h"
#include "edsp/request_kinds.h"

namespace edsp {

namespace {

// A move asked to go slower than this share of the config's speed is a
// typo (and one longer than kLongestMove_s, planned_motion.h).
constexpr double kSlowestShare = 1e-3;
constexpr double kMaxFrameOffset_m = 100.0;
constexpr double kMaxPivotOffset_m = 10.0;

bool AllFinite(const double* v, int n) {
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(v[k])) return false;
  }
  return true;
}

// One requested limit: 0 keeps `current`; else it must be in [most/1000, most].
Problem TakeLimit(double asked, double most, const char* field, const char* key, double* current) {
  if (asked == 0.0) return std::nullopt;
  if (!std::isfinite(asked) || asked < most * kSlowestShare || asked > most) {
    return fmt::format("{} = {} is not in [{}, {}] (the config's [motion] {} and a thousandth of it)", field, asked,
                       most * kSlowestShare, most, key);
  }
  *current = asked;
  return std::nullopt;
}

}  // namespace

std::string RequestKindName(std::int8_t kind) {
  const RequestKindRow* row = FindRequestKind(kind);
  return row != nullptr ? std::string(row->name) : fmt::format("kind {}", kind);
}

std::string PoseText(const Vector6& q) {
  return fmt::format("({:.6f}, {:.6f}, {:.6f} m; {:.6f}, {:.6f}, {:.6f} rad)", q(0), q(1), q(2), q(3), q(4), q(5));
}

Vector6 RequestPose(const motion_request_t& r) {
  Vector6 q;
  for (int k = 0; k < 6; ++k) q(k) = r.pose[k];
  return q;
}

Problem PoseProblem(const motion_request_t& r) {
  if (AllFinite(r.pose, 6)) return std::nullopt;
  return "pose has a non-finite value (NaN or infinity)";
}

int JogAxisIndex(std::string_view name) {
  for (int k = 0; k < 6; ++k) {
    if (name == kJogAxes[k]) return k;
  }
  return -1;
}

Problem JogProblem(const motion_request_t& r) {
  int axis = -1;
  std::string axes;
  for (int k = 0; k < 6; ++k) {
    if (!std::isfinite(r.pose[k]))
      return fmt::format("jog step along {} = {}: give a finite step", kJogAxes[k], r.pose[k]);
    if (r.pose[k] == 0.0) continue;
    axes += (axes.empty() ? "" : ", ") + std::string(kJogAxes[k]);
    axis = axis < 0 ? k : 6;  // 6: more than one
  }
  if (axis < 0) return "jog step is zero (every pose value is 0): give one axis a nonzero step";
  if (axis == 6) {
    return fmt::format("jog steps along {}: a jog moves along one axis (move --relative for more)", axes);
  }
  const char* unit = axis < 3 ? "m" : "rad";
  if (std::abs(r.pose[axis]) > kJogStepMax) {
    return fmt::format("jog step along {} = {} {} is beyond {} {} (a jog is small: move --relative for more)",
                       kJogAxes[axis], r.pose[axis], unit, kJogStepMax, unit);
  }
  return std::nullopt;
}

Problem FrameDefinitionProblem(const motion_request_t& r) {
  const std::string& name = r.frame;
  if (name.empty() || name == "base" || name == "home") {
    return fmt::format("frame name \"{}\": give a new name (base and home are built in)", name);
  }
  if (!AllFinite(r.pose, 6)) return fmt::format("frame {}: pose has a non-finite value", name);
  const double offset_m = Pose::FromVector(RequestPose(r)).p_BoMo_B.norm();
  if (offset_m > kMaxFrameOffset_m) {
    return fmt::format("frame {}: origin {:.3f} m from {{B}}, beyond {} m", name, offset_m, kMaxFrameOffset_m);
  }
  return std::nullopt;
}

Problem PivotProblem(const motion_request_t& r) {
  const Vector3 c(r.point[0], r.point[1], r.point[2]);
  if (c.allFinite() && c.norm() <= kMaxPivotOffset_m) return std::nullopt;
  return fmt::format("pivot ({}, {}, {}) m: give a finite point within {} m of {{M}}'s origin", c(0), c(1), c(2),
                     kMaxPivotOffset_m);
}

Problem ProgramProblem(const motion_request_t& r) {
  if (r.motions.empty() != r.csv_text.empty()) return std::nullopt;
  return "give either motions or a CSV, not both";
}

Problem SpeedLimitsProblem(const motion_request_t& r, const MoveLimits& most, MoveLimits* limits) {
  Problem p = TakeLimit(r.speed_m_s, most.speed_m_s, "speed_m_s", "speed_max_m_s", &limits->speed_m_s);
  if (!p) p = TakeLimit(r.speed_rad_s, most.speed_rad_s, "speed_rad_s", "speed_max_rad_s", &limits->speed_rad_s);
  return p;
}

Problem AllLimitsProblem(const motion_request_t& r, const MoveLimits& most, MoveLimits* limits) {
  Problem p = SpeedLimitsProblem(r, most, limits);
  if (!p) p = TakeLimit(r.accel_m_s2, most.accel_m_s2, "accel_m_s2", "accel_max_m_s2", &limits->accel_m_s2);
  if (!p) {
    p = TakeLimit(r.accel_rad_s2, most.accel_rad_s2, "accel_rad_s2", "accel_max_rad_s2", &limits->accel_rad_s2);
  }
  return p;
}

}  // namespace edsp
