#include "edsp/planner/identifiability.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

namespace edsp {

using calibration::Effect;

namespace {

// Joint-centre errors that only move the whole base (a translation, a
// small rotation of every base joint together) are a change of the
// tracker's frame: no motion can tell them apart. The basis of the other
// 30 directions, orthonormal.
Eigen::MatrixXd JointPositionsApartFromTheFrame(const PlatformModel& model) {
  const int n = calibration::ParameterCount(Effect::kJointPosition);
  Eigen::MatrixXd rigid = Eigen::MatrixXd::Zero(n, 6);
  for (int i = 0; i < 6; ++i) {
    rigid.block<3, 3>(3 * i, 0) = Matrix3::Identity();
    rigid.block<3, 3>(3 * i, 3) = -calibration::Skew(model.config().geometry.p_BoBi_B.col(i));
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(rigid);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(n, n);
  return Q.rightCols(n - 6);
}

// Raw parameters of the effect → the scaled (and, where the vocabulary has
// directions no data can separate, reduced) parameters judged.
Eigen::MatrixXd ScaleOf(Effect effect, const PlatformModel& model, PrMode pr_mode) {
  const int n = calibration::ParameterCount(effect);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) D(k, k) = calibration::TypicalParameterSize(effect, k);
  if (effect == Effect::kJointPosition) return D * JointPositionsApartFromTheFrame(model);
  // The applied compensation's scale differs from the signed PR's only when
  // the commands carried the paper's unsigned compensation.
  if (effect == Effect::kPassiveRotation && pr_mode != PrMode::kUnsigned) return D.leftCols(1);
  return D;
}

// A structural mode's columns need its frequency, which the data decides
// (edsp-gap's structural_mode_fit.h), and every motion that accelerates
// excites it: the motion design does not judge it.
bool Judged(Effect e) { return e != Effect::kStructuralResonance; }

}  // namespace

std::vector<Effect> JointlyIdentifiedEffects() {
  std::vector<Effect> effects;
  for (Effect e : calibration::AllEffects()) {
    if (e != Effect::kLegOffset && Judged(e)) effects.push_back(e);
  }
  return effects;
}

IdentificationInformation::IdentificationInformation(const PlatformModel& model, std::vector<Effect> effects,
                                                     const IdentifiabilityOptions& options)
    : model_(&model), effects_(std::move(effects)), row_scale_(1.0 / options.noise_sigma_m) {
  int columns = 6;
  for (Effect e : effects_) {
    scale_.push_back(ScaleOf(e, model, options.pr_mode));
    columns += static_cast<int>(scale_.back().cols());
  }
  information_ = Eigen::MatrixXd::Zero(columns, columns);
}

PointSensitivity PointSensitivityAt(const PlatformModel& model, const Pose& pose) {
  PointSensitivity at;
  if (!calibration::PointSensitivityAt(model, pose, &at)) {
    throw std::invalid_argument("identifiability: the pose " + DescribePose(pose) + " is singular for the model");
  }
  return at;
}

void IdentificationInformation::Add(const PointSensitivity& at, const calibration::LegErrorState& state) {
  Eigen::MatrixXd rows(3, information_.cols());
  rows.leftCols<3>() = Matrix3::Identity();
  rows.block<3, 3>(0, 3) = -calibration::Skew(at.point);
  int column = 6;
  for (std::size_t k = 0; k < effects_.size(); ++k) {
    const Eigen::Index width = scale_[k].cols();
    rows.middleCols(column, width) = at.per_leg * calibration::LegErrorBasis(effects_[k], state, *model_) * scale_[k];
    column += static_cast<int>(width);
  }
  rows *= row_scale_;
  information_.selfadjointView<Eigen::Lower>().rankUpdate(rows.transpose());
  ++samples_;
}

Eigen::MatrixXd IdentificationInformation::ParameterInformation() const {
  const Eigen::MatrixXd full = Full();
  const Eigen::Index p = full.rows() - 6;
  const Eigen::MatrixXd Iff = full.topLeftCorner(6, 6);
  const Eigen::MatrixXd Ifp = full.topRightCorner(6, p);
  return full.bottomRightCorner(p, p) - Ifp.transpose() * Iff.ldlt().solve(Ifp);
}

Identifiability Summarize(const std::string& name, const IdentificationInformation& information) {
  Identifiability out;
  out.effects = name;
  out.parameters = information.parameters();
  out.samples = information.samples();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(information.ParameterInformation(),
                                                             Eigen::EigenvaluesOnly);
  const Eigen::VectorXd sigma = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
  out.o3 = sigma(0);
  out.condition = sigma(0) > 0.0 ? sigma(sigma.size() - 1) / sigma(0) : std::numeric_limits<double>::infinity();
  double log_sum = 0.0;
  for (Eigen::Index k = 0; k < sigma.size(); ++k) log_sum += std::log(std::max(sigma(k), 1e-300));
  out.o1 = std::exp(log_sum / static_cast<double>(sigma.size())) / std::sqrt(std::max(1, out.samples));
  return out;
}

calibration::LegErrorInputs ErrorInputsAt(const PlatformModel& model, const Trajectory& trajectory, double t_s,
                                          PrMode pr_mode) {
  constexpr double h = 1e-3;
  auto command = [&](double t) {
    return model.CompensatedLengths(Pose::FromVector(trajectory.Sample(t).pose), pr_mode);
  };
  const PoseSample sample = trajectory.Sample(t_s);
  const Vector6 c = command(t_s), p1 = command(t_s + h), m1 = command(t_s - h);
  const Vector6 p2 = command(t_s + 2.0 * h), m2 = command(t_s - 2.0 * h);
  calibration::LegErrorInputs in;
  in.time_s = t_s;
  in.pose = Pose::FromVector(sample.pose);
  in.command_m = c;
  in.motor_m = c;
  in.velocity = (p1 - m1) / (2.0 * h);
  in.accel = (p1 - 2.0 * c + m1) / (h * h);
  in.jerk = (p2 - 2.0 * p1 + 2.0 * m1 - m2) / (2.0 * h * h * h);
  in.platform_accel_B_m_s2 = sample.acceleration.head<3>();
  return in;
}

std::vector<Identifiability> AssessIdentifiability(const PlatformModel& model, const Trajectory& trajectory,
                                                   const IdentifiabilityOptions& options) {
  std::vector<IdentificationInformation> sets;
  std::vector<std::string> names = {"all"};
  sets.emplace_back(model, JointlyIdentifiedEffects(), options);
  for (Effect e : calibration::AllEffects()) {
    if (!Judged(e)) continue;
    sets.emplace_back(model, std::vector<Effect>{e}, options);
    names.emplace_back(calibration::EffectName(e));
  }
  calibration::LegErrorTracker tracker(model, options.errors);
  const int samples = static_cast<int>(std::floor(trajectory.duration_s() * options.rate_hz)) + 1;
  for (int k = 0; k < samples; ++k) {
    const calibration::LegErrorInputs in =
        ErrorInputsAt(model, trajectory, static_cast<double>(k) / options.rate_hz, options.pr_mode);
    const calibration::LegErrorState state = tracker.Advance(in);
    const PointSensitivity at = PointSensitivityAt(model, in.pose);
    for (IdentificationInformation& set : sets) set.Add(at, state);
  }
  std::vector<Identifiability> out;
  for (std::size_t k = 0; k < sets.size(); ++k) out.push_back(Summarize(names[k], sets[k]));
  return out;
}

}  // namespace edsp
