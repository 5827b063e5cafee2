#include "edsp/kinematics/calibration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/kinematics/finite_difference.h"

namespace edsp::calibration {

namespace {

std::string Fnv1a64Hex(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CalibrationError(path + ": cannot open the calibration model");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

enum class Lowest { kAboveZero, kZero };

// `key` of `j` in (0, max] or [0, max], `fallback` when absent; the error
// names the key and the value.
double NumberIn(const nlohmann::json& j, const char* key, double fallback, Lowest lowest, double max,
                const std::string& origin) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) throw CalibrationError(fmt::format("{}: \"{}\" must be a number", origin, key));
  const double v = j[key].get<double>();
  const bool zero_allowed = lowest == Lowest::kZero;
  if (!((zero_allowed ? v >= 0.0 : v > 0.0) && v <= max)) {
    throw CalibrationError(
        fmt::format("{}: \"{}\" = {} is not in {}0, {}]", origin, key, v, zero_allowed ? "[" : "(", max));
  }
  return v;
}

// A's acceleration along the commanded path: the second difference of A
// over the pose's quadratic about now (exact to O(h²); the pose's angles
// are not an angular velocity, so differencing A is simpler than the
// rigid-body formula).
Vector3 PointAcceleration(const PlatformModel& model, const Vector6& q, const Vector6& velocity,
                          const Vector6& acceleration) {
  constexpr double h = 1e-3;  // s
  const Vector6 ahead = q + h * velocity + 0.5 * h * h * acceleration;
  const Vector6 behind = q - h * velocity + 0.5 * h * h * acceleration;
  return SecondDerivative<Vector3>(model.ObservationPoint(Pose::FromVector(behind)),
                                   model.ObservationPoint(Pose::FromVector(q)),
                                   model.ObservationPoint(Pose::FromVector(ahead)), h, h);
}

// An entry's "verdict"; a file without one (saved before verdicts) holds
// identified effects.
Verdict EntryVerdict(const nlohmann::json& entry, const std::string& where, const std::string& name) {
  if (!entry.contains("verdict")) return Verdict::kIdentified;
  if (!entry["verdict"].is_string()) {
    throw CalibrationError(fmt::format("{} ({}): \"verdict\" must be a string", where, name));
  }
  const std::string text = entry["verdict"].get<std::string>();
  const std::optional<Verdict> verdict = VerdictFromName(text);
  if (!verdict) {
    throw CalibrationError(
        fmt::format("{} ({}): verdict \"{}\" is not identified, ambiguous or rejected", where, name, text));
  }
  return *verdict;
}

CalibratedEffect ParseEffectEntry(const nlohmann::json& entry, std::size_t index, const std::string& origin) {
  const std::string where = fmt::format("{}: effects[{}]", origin, index);
  if (!entry.is_object() || !entry.contains("name") || !entry["name"].is_string()) {
    throw CalibrationError(where + ": needs a \"name\"");
  }
  CalibratedEffect out;
  const std::string name = entry["name"].get<std::string>();
  if (!ParseEffect(name, &out.effect)) throw CalibrationError(fmt::format("{}: unknown effect \"{}\"", where, name));
  if (!entry.contains("theta") || !entry["theta"].is_array()) {
    throw CalibrationError(fmt::format("{} ({}): needs a \"theta\" array", where, name));
  }
  std::vector<double> theta;
  for (const auto& v : entry["theta"]) {
    if (!v.is_number()) throw CalibrationError(fmt::format("{} ({}): \"theta\" holds a non-number", where, name));
    theta.push_back(v.get<double>());
  }
  // Models saved before thermal drift had its time driver hold the travel term alone.
  if (out.effect == Effect::kThermalDrift && theta.size() == 1) theta.resize(4, 0.0);
  if (static_cast<int>(theta.size()) != ParameterCount(out.effect)) {
    throw CalibrationError(
        fmt::format("{} ({}): needs {} parameters, has {}", where, name, ParameterCount(out.effect), theta.size()));
  }
  for (std::size_t k = 0; k < theta.size(); ++k) {
    if (!std::isfinite(theta[k]))
      throw CalibrationError(fmt::format("{} ({}): theta[{}] is not finite", where, name, k));
  }
  out.theta = Eigen::Map<const Eigen::VectorXd>(theta.data(), static_cast<Eigen::Index>(theta.size()));
  out.verdict = EntryVerdict(entry, where, name);
  if (entry.contains("apply") && !entry["apply"].is_boolean()) {
    throw CalibrationError(fmt::format("{} ({}): \"apply\" must be true or false", where, name));
  }
  out.has_apply = entry.contains("apply");
  out.apply = out.has_apply && entry["apply"].get<bool>();
  return out;
}

}  // namespace

std::vector<int> UnappliedParameters(Effect effect) {
  if (effect == Effect::kServoLag) return {12};  // jerk_lag_s3 (leg_effects.cpp), not fed forward
  return {};
}

bool AppliesEntry(Verdict verdict, bool has_apply, bool apply, bool apply_ambiguous) {
  if (apply_ambiguous && verdict == Verdict::kAmbiguous) return true;
  return has_apply ? apply : verdict == Verdict::kIdentified;
}

std::string PlatformFingerprint(const PlatformModel& model) {
  const Vector6& l = model.home_length_m();
  const DriveParameters& d = model.config().drive;
  return fmt::format(
      "home_length_m={:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f};lead_m={:.9g};pr_sign={};gear_ratio={:.9g}", l(0), l(1),
      l(2), l(3), l(4), l(5), d.lead_m, d.pr_sign, d.gear_ratio);
}

std::string CalibrationModel::Describe() const {
  std::string applies;
  for (const CalibratedEffect& e : applied)
    applies += (applies.empty() ? "" : ", ") + std::string(EffectName(e.effect));
  std::string text = fmt::format("{} ({}): applies {}", origin, hash, applies.empty() ? "nothing" : applies);
  if (!not_applied.empty()) {
    text += "; not applied: ";
    for (std::size_t k = 0; k < not_applied.size(); ++k) text += (k ? ", " : "") + not_applied[k];
  }
  return text;
}

CalibrationModel ParseCalibration(const std::string& text, const std::string& origin, const PlatformModel& model,
                                  bool apply_ambiguous) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw CalibrationError(fmt::format("{}: not JSON at byte {}", origin, e.byte));
  }
  if (!j.is_object() || !j.contains("format") || !j["format"].is_string() ||
      j["format"].get<std::string>() != "edsp-gap-model/1") {
    throw CalibrationError(origin + ": not an edsp-gap model (key \"format\" must be \"edsp-gap-model/1\")");
  }
  if (j.contains("platform")) {
    const std::string expected = PlatformFingerprint(model);
    if (!j["platform"].is_string() || j["platform"].get<std::string>() != expected) {
      throw CalibrationError(fmt::format("{}: identified on another platform (\"platform\": {}; this config: \"{}\")",
                                         origin, j["platform"].dump(), expected));
    }
  }
  CalibrationModel out;
  out.origin = origin;
  out.hash = Fnv1a64Hex(text);
  out.options.thermal_time_constant_s =
      NumberIn(j, "thermal_time_constant_s", out.options.thermal_time_constant_s, Lowest::kAboveZero, 1e6, origin);
  out.options.backlash_width_m =
      NumberIn(j, "backlash_width_m", out.options.backlash_width_m, Lowest::kAboveZero, 1e-3, origin);
  out.options.structural_mode_hz = NumberIn(j, "structural_mode_hz", 0.0, Lowest::kZero, 100.0, origin);
  out.options.structural_mode_damping =
      NumberIn(j, "structural_mode_damping", out.options.structural_mode_damping, Lowest::kZero, 1.0, origin);
  if (!j.contains("effects") || !j["effects"].is_array()) throw CalibrationError(origin + ": no \"effects\" array");
  std::array<bool, kEffectCount> seen{};
  for (std::size_t k = 0; k < j["effects"].size(); ++k) {
    CalibratedEffect e = ParseEffectEntry(j["effects"][k], k, origin);
    bool& twice = seen[static_cast<std::size_t>(e.effect)];
    if (twice) throw CalibrationError(fmt::format("{}: effect \"{}\" listed twice", origin, EffectName(e.effect)));
    twice = true;
    if (!AppliesEntry(e.verdict, e.has_apply, e.apply, apply_ambiguous)) {
      out.not_applied.push_back(std::string(EffectName(e.effect)) + " (" + VerdictName(e.verdict) + ")");
      continue;
    }
    // What is applied must be a real platform's (an entry left out, a named
    // effect beside the calibration set, commands nothing).
    for (Eigen::Index t = 0; t < e.theta.size(); ++t) {
      if (std::abs(e.theta(t)) > ParameterLimit(e.effect)) {
        throw CalibrationError(fmt::format("{}: effects[{}] ({}): theta[{}] = {} is not a real platform's (|θ| ≤ {})",
                                           origin, k, EffectName(e.effect), t, e.theta(t), ParameterLimit(e.effect)));
      }
    }
    if (e.effect == Effect::kStructuralResonance && !(out.options.structural_mode_hz > 0.0)) {
      throw CalibrationError(origin + ": effect \"structural_resonance\" needs \"structural_mode_hz\" > 0");
    }
    out.applied.push_back(std::move(e));
  }
  RequireWithinTheStrokes(out, model);
  return out;
}

void RequireWithinTheStrokes(const CalibrationModel& calibration, const PlatformModel& model) {
  // At home, at rest: the static part of the correction, which every start
  // and every dwell carries.
  LegCompensator at_home(model, calibration);
  const Pose home = model.home_pose();
  const Vector6 nominal = model.Solve(home).length_m - model.PrLengthError(model.Solve(home), PrMode::kSigned);
  const Vector6 correction = at_home.Step(0.0, home, Vector6::Zero(), Vector6::Zero(), nominal).command_m;
  const WorkspaceLimits& limits = model.config().limits;
  for (int i = 0; i < kNumLegs; ++i) {
    const double length = nominal(i) - correction(i);
    if (!std::isfinite(length) || length < limits.leg_min_m || length > limits.leg_max_m) {
      throw CalibrationError(
          fmt::format("{}: leg {} at home would be commanded {:.6f} m (a correction of {:.6f} m), outside its stroke "
                      "{:.3f}..{:.3f} m: not a calibration of this platform",
                      calibration.origin, i + 1, length, -correction(i), limits.leg_min_m, limits.leg_max_m));
    }
  }
}

CalibrationModel LoadCalibration(const std::string& path, const PlatformModel& model, bool apply_ambiguous) {
  return ParseCalibration(ReadFile(path), path, model, apply_ambiguous);
}

namespace {

// The compensator's tracker without the structural mode: the sway it
// cancels follows the inverse mode (StructuralSway), not the fitted one.
LegErrorOptions WithoutTheMode(LegErrorOptions options) {
  options.structural_mode_hz = 0.0;
  return options;
}

}  // namespace

LegCompensator::LegCompensator(PlatformModel model, CalibrationModel calibration)
    : model_(model),
      calibration_(std::move(calibration)),
      tracker_(std::move(model), WithoutTheMode(calibration_.options)) {}

LegCompensator::Correction LegCompensator::Step(double time_s, const Pose& pose, const Vector6& pose_velocity,
                                                const Vector6& pose_acceleration, const Vector6& command_m) {
  // The command's rates from the pose's: l̇ = M·q̇, l̈ = M·q̈ + (dM/dt)·q̇,
  // M = ∂(IK − PR)/∂q, its change along q̇ by a central difference.
  const Vector6 q = pose.ToVector();
  const Matrix6 M = model_.LengthJacobian(pose) - model_.PrLengthErrorJacobian(pose);
  LegErrorInputs in;
  in.time_s = time_s;
  in.pose = pose;
  // The stroke is where the screw turns to: the command with the
  // correction subtracted, not the nominal one (a periodic error's phase
  // moves 2π·Δl/lead: 0.1 rad for 150 µm of correction on a 10 mm lead).
  // The last correction stands in for this one, which differs from it by
  // at most kMaxCorrectionRate_m_s × the cycle. The play follows the
  // nominal command's reversals: fed the corrected one, the correction's
  // own ramp from zero at the start flips it, and a whole rig's held-out
  // error after calibration grows by a third
  // (WholeRigCalibration.TheDesignedMotionsCalibrateAWholeRig).
  in.command_m = command_m - last_command_m_;
  in.motor_m = command_m;
  in.velocity = M * pose_velocity;
  in.accel = M * pose_acceleration;
  if (pose_velocity.norm() > 0.0) {
    constexpr double h = 1e-4;  // s
    const Pose ahead = Pose::FromVector(q + h * pose_velocity), behind = Pose::FromVector(q - h * pose_velocity);
    const Matrix6 dM = (model_.LengthJacobian(ahead) - model_.PrLengthErrorJacobian(ahead) -
                        model_.LengthJacobian(behind) + model_.PrLengthErrorJacobian(behind)) /
                       (2.0 * h);
    in.accel += dM * pose_velocity;
  }
  in.jerk = Vector6::Zero();  // not fed forward: a trapezoid's corners would make it a spike
  in.platform_accel_B_m_s2 = pose_acceleration.head<3>();
  in.point_accel_B_m_s2 = PointAcceleration(model_, q, pose_velocity, pose_acceleration);
  LegErrorState state = tracker_.Advance(in);
  state.compensation -= last_command_m_;  // the PR's alone, as the diagnosis's basis takes it
  Correction c;
  for (const CalibratedEffect& e : calibration_.applied) {
    const Vector6 dl = e.effect == Effect::kStructuralResonance
                           ? StructuralSway(e, time_s, in)
                           : Vector6(LegErrorBasis(e.effect, state, model_) * e.theta);
    c.command_m += dl;
    // The encoders see the servo's lag themselves, and the structure's sway
    // is not in the legs at all: forward kinematics finds the platform, not A.
    if (e.effect != Effect::kServoLag && e.effect != Effect::kStructuralResonance) c.encoder_m += dl;
  }
  // A setpoint stream whose velocity jumps (a CSV trajectory's rows, a
  // start from rest) would make the feed-forward step: the correction
  // moves at most kMaxCorrectionRate_m_s, so no step reaches the drives.
  if (last_time_s_) {
    const double max_step = kMaxCorrectionRate_m_s * std::max(0.0, time_s - *last_time_s_);
    c.command_m = last_command_m_ + (c.command_m - last_command_m_).cwiseMax(-max_step).cwiseMin(max_step);
  }
  last_time_s_ = time_s;
  last_command_m_ = c.command_m;
  return c;
}

Vector6 LegCompensator::StructuralSway(const CalibratedEffect& e, double time_s, const LegErrorInputs& in) {
  // The legs that cancel the sway move the platform, and so the base the
  // mode hangs from: with the command corrected by c, the sway s follows
  // s̈ + 2ζωṡ + ω²s = −g·(a − s̈), i.e. the mode with mass 1 − g.
  const Vector3 gain = e.theta.head<3>().cwiseMin(1.0 - kMinModeMass);
  if (!inverse_mode_) {
    const Vector3 mass = Vector3::Ones() - gain;
    inverse_mode_.emplace(calibration_.options.structural_mode_hz, calibration_.options.structural_mode_damping, mass);
  }
  const Vector3& x = inverse_mode_->Advance(time_s - last_mode_time_s_, in.point_accel_B_m_s2);
  last_mode_time_s_ = time_s;
  return TranslationToLegs(model_, in.pose) * gain.cwiseProduct(x);
}

}  // namespace edsp::calibration
