#include "edsp/diagnosis/design.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <fmt/format.h>

#include "edsp/kinematics/finite_difference.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "edsp/kinematics/leg_error_model.h"

namespace edsp::gap {

namespace {

// Central difference of a per-row quantity within one run (one-sided at its ends).
template <typename Get>
Vector6 Derivative(const std::vector<int>& rows, std::size_t k, const MeasurementData& data, Get get) {
  const std::size_t lo = k == 0 ? 0 : k - 1;
  const std::size_t hi = k + 1 < rows.size() ? k + 1 : k;
  if (lo == hi) return Vector6::Zero();
  const MeasurementRow& a = data.rows[static_cast<std::size_t>(rows[lo])];
  const MeasurementRow& b = data.rows[static_cast<std::size_t>(rows[hi])];
  const double dt = b.time_s - a.time_s;
  if (dt <= 0.0) return Vector6::Zero();
  return (get(b) - get(a)) / dt;
}

std::vector<std::vector<int>> RowsByRun(const MeasurementData& data) {
  std::vector<std::vector<int>> rows(data.runs.size());
  for (std::size_t k = 0; k < data.rows.size(); ++k) {
    rows[static_cast<std::size_t>(data.rows[k].run)].push_back(static_cast<int>(k));
  }
  return rows;
}

}  // namespace

void EstimateFrame(const std::vector<Vector3>& model_points, const std::vector<Vector3>& measured, Matrix3* R,
                   Vector3* t) {
  const Eigen::Index n = static_cast<Eigen::Index>(model_points.size());
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    src.col(k) = model_points[static_cast<std::size_t>(k)];
    dst.col(k) = measured[static_cast<std::size_t>(k)];
  }
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, false);
  *R = T.topLeftCorner<3, 3>();
  *t = T.topRightCorner<3, 1>();
}

bool FixesFrameRotation(const std::vector<Vector3>& points, double min_spread_m) {
  if (points.size() < 3) return false;
  Vector3 mean = Vector3::Zero();
  for (const Vector3& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Matrix3 scatter = Matrix3::Zero();
  for (const Vector3& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Vector3 variances =
      Eigen::SelfAdjointEigenSolver<Matrix3>(scatter / static_cast<double>(points.size())).eigenvalues();  // ascending
  return std::sqrt(std::max(variances(1), 0.0)) >= min_spread_m;
}

Eigen::VectorXd ResidualInFrame(const Design& d, const Matrix3& R, const Eigen::VectorXd& predicted_B) {
  const std::size_t n = d.model_point.size();
  Eigen::VectorXd r(d.residual.size());
  Vector3 mean = Vector3::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    const auto row = static_cast<Eigen::Index>(3 * k);
    const Vector3 measured = d.residual.segment<3>(row) + d.R0 * d.model_point[k] + d.t0;
    r.segment<3>(row) = measured - R * (d.model_point[k] + predicted_B.segment<3>(row));
    mean += r.segment<3>(row);
  }
  mean /= static_cast<double>(std::max<std::size_t>(n, 1));
  for (std::size_t k = 0; k < n; ++k) r.segment<3>(static_cast<Eigen::Index>(3 * k)) -= mean;
  return r;
}

namespace {

// The leg-space state at every sample, in run order, and what the columns need of it.
struct Samples {
  std::vector<calibration::LegErrorState> states;
  std::vector<Eigen::Matrix<double, 3, 6>> G;  // ∂A/∂l at each sample, {B}
  std::vector<Vector3> model_points, measured;
  // The PR the controller compensated: the signed model's and Eq. (9)'s at
  // the commanded pose (what ClassifyAppliedPr compares the record with).
  std::vector<Vector6> commanded_pr_signed, commanded_pr_unsigned;
  // How far the legs stood from their commands where the samples are taken
  // about the encoders' pose (zero where about the commanded one).
  std::vector<Vector6> behind;
};

// Places every effect's θ after the frame's 6 columns and sizes the rows.
void LayOutColumns(int samples, Design* d) {
  d->frame = {0, 6};
  int column = 6;
  for (Effect e : AllEffects()) {
    d->effect[static_cast<std::size_t>(e)] = {column, ParameterCount(e)};
    column += ParameterCount(e);
  }
  d->residual.resize(3 * samples);
  d->columns.setZero(3 * samples, column);
}

// Leg velocity, acceleration and the platform's and A's acceleration at
// row k of a run, from the commands (central differences; none at a run's ends).
void CommandRates(const PlatformModel& model, const MeasurementData& data, const std::vector<int>& rows, std::size_t k,
                  calibration::LegErrorInputs* in) {
  in->velocity = Derivative(rows, k, data, [](const MeasurementRow& r) { return r.leg_cmd_m; });
  const std::size_t lo = k == 0 ? 0 : k - 1, hi = k + 1 < rows.size() ? k + 1 : k;
  const MeasurementRow& a = data.rows[static_cast<std::size_t>(rows[lo])];
  const MeasurementRow& row = data.rows[static_cast<std::size_t>(rows[k])];
  const MeasurementRow& b = data.rows[static_cast<std::size_t>(rows[hi])];
  const double h1 = row.time_s - a.time_s, h2 = b.time_s - row.time_s;
  if (lo + 1 == k && hi == k + 1 && h1 > 0.0 && h2 > 0.0) {
    in->accel = SecondDerivative<Vector6>(a.leg_cmd_m, row.leg_cmd_m, b.leg_cmd_m, h1, h2);
    in->platform_accel_B_m_s2 =
        SecondDerivative<Vector3>(a.pose_cmd.head<3>(), row.pose_cmd.head<3>(), b.pose_cmd.head<3>(), h1, h2);
    auto point = [&](const MeasurementRow& r) { return model.ObservationPoint(Pose::FromVector(r.pose_cmd)); };
    in->point_accel_B_m_s2 = SecondDerivative<Vector3>(point(a), point(row), point(b), h1, h2);
  }
}

// The moment about {B}'s origin of 1 kg at {M}'s origin under `force` per
// kg (its weight and translational inertia), then per kg·m of c.o.m. offset
// along {M}'s axes: (p + R·c) × F expanded in c.
Eigen::Matrix<double, 3, 4> LoadMoment(const Pose& pose, const Vector3& force) {
  Eigen::Matrix<double, 3, 4> moment;
  const Matrix3 R = RotationFromRpy(pose.rpy_rad);
  moment.col(0) = pose.p_BoMo_B.cross(force);
  for (int a = 0; a < 3; ++a) moment.col(1 + a) = R.col(a).cross(force);
  return moment;
}

// Where the platform stood with its legs `behind` their commands (the
// encoders' lengths − the commands'); the commanded pose where that cannot be
// solved. A soft drive loop trails its command by millimetres, milliradians
// in a rotation: every effect's columns and the model's point are taken
// about that pose, so that neither the kinematics' curvature nor an effect
// seen from a pose a few milliradians off (joint centres turned with the
// platform) is left as structure. The linear part of the lag stays for
// servo_lag (FillColumns).
Pose WhereTheLegsStood(const PlatformModel& model, const Pose& commanded, const Vector6& behind) {
  if (behind.isZero(0.0)) return commanded;
  FkOptions fk;
  fk.tolerance_m = 1e-9;  // a nanometre: far under any effect, two steps from millimetres
  const FkResult stood = SolveForward(model, model.EncoderLengths(commanded) + behind, commanded, fk);
  return stood.ok() ? stood.pose : commanded;
}

// The pose a sample is taken about (WhereTheLegsStood) and ∂A/∂l there into
// `at`; the commanded pose, `behind` zeroed, where that one is singular; a
// pose that is not finite where the commanded one is singular too.
Pose PoseToTakeAbout(const PlatformModel& model, const Pose& commanded, Vector6* behind,
                     calibration::PointSensitivity* at) {
  const Pose stood = WhereTheLegsStood(model, commanded, *behind);
  const bool moved = stood.ToVector() != commanded.ToVector();
  if (moved && calibration::PointSensitivityAt(model, stood, at)) return stood;
  behind->setZero();
  if (calibration::PointSensitivityAt(model, commanded, at)) return commanded;
  return Pose::FromVector(Vector6::Constant(std::numeric_limits<double>::quiet_NaN()));
}

// Pass 1: the model's point and the leg-space state of every sample, in run
// order (play and heat carry over from run to run, as on the rig).
Samples TrackSamples(const PlatformModel& model, const MeasurementData& data, const DesignOptions& o, Design* d) {
  Samples out;
  calibration::LegErrorTracker tracker(model, o);
  const std::vector<std::vector<int>> by_run = RowsByRun(data);
  for (std::size_t run = 0; run < by_run.size(); ++run) {
    const std::vector<int>& rows = by_run[run];
    d->run_samples.push_back({static_cast<int>(d->sample_run.size()), static_cast<int>(rows.size())});
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const MeasurementRow& row = data.rows[static_cast<std::size_t>(rows[k])];
      const Pose commanded = Pose::FromVector(row.pose_cmd);
      Vector6 behind = d->has_encoder ? Vector6(row.leg_enc_m - row.leg_cmd_m) : Vector6::Zero();
      calibration::PointSensitivity at;
      const Pose pose = PoseToTakeAbout(model, commanded, &behind, &at);
      if (!pose.IsFinite()) {
        throw MeasurementError(fmt::format("{}: run \"{}\" at time_s {}: commanded pose {} is singular for the model",
                                           data.source, data.runs[run], row.time_s, DescribePose(commanded)));
      }
      out.G.push_back(at.per_leg);
      out.behind.push_back(behind);
      calibration::LegErrorInputs in;
      in.time_s = row.time_s;
      in.pose = pose;
      // Where a row has encoders the motor's own motion drives the play, and
      // the screw's travel, not the command's, sets where the thread's errors
      // and the nut's heat are: a soft loop trails its command by millimetres,
      // a good part of a thread error's period.
      in.command_m = row.has_encoder ? row.leg_enc_m : row.leg_cmd_m;
      in.motor_m = in.command_m;
      CommandRates(model, data, rows, k, &in);
      calibration::LegErrorState s = tracker.Advance(in);
      const LegSolution legs_commanded = model.Solve(commanded);
      // The compensation is what the controller applied, at the commanded
      // pose; the one the PR basis scales is the PR's alone: a calibration's
      // correction recorded with the command is not part of it.
      s.compensation = legs_commanded.length_m - row.leg_cmd_m - row.leg_corr_m;
      out.commanded_pr_signed.push_back(model.PrLengthError(legs_commanded, PrMode::kSigned));
      out.commanded_pr_unsigned.push_back(model.PrLengthError(legs_commanded, PrMode::kUnsigned));
      out.states.push_back(s);
      out.model_points.push_back(model.ObservationPoint(pose));
      out.measured.push_back(row.point_m);
      d->sample_run.push_back(static_cast<int>(run));
      d->source_row.push_back(rows[k]);
      d->time_s.push_back(row.time_s);
      d->leg_velocity_m_s.push_back(s.velocity);
      d->leg_accel_m_s2.push_back(s.accel);
      d->point_accel_m_s2.push_back(in.point_accel_B_m_s2);
      d->load_moment_per_kg.push_back(LoadMoment(pose, o.gravity_B_m_s2 - in.platform_accel_B_m_s2));
      d->servo_error_m.push_back(d->has_encoder ? Vector6(row.leg_cmd_m - row.leg_enc_m) : Vector6::Zero());
      d->displacement.push_back((row.pose_cmd - model.home_pose().ToVector()).norm());
    }
  }
  return out;
}

// Jerk: the central difference of the acceleration within each run.
void AddJerk(const Design& d, std::vector<calibration::LegErrorState>* states) {
  for (const ColumnRange& run : d.run_samples) {
    for (int k = run.begin; k < run.begin + run.count; ++k) {
      calibration::LegErrorState& s = (*states)[static_cast<std::size_t>(k)];
      s.jerk = Vector6::Zero();
      if (k == run.begin || k + 1 == run.begin + run.count) continue;
      const double span = d.time_s[static_cast<std::size_t>(k + 1)] - d.time_s[static_cast<std::size_t>(k - 1)];
      if (span > 0.0) {
        s.jerk = ((*states)[static_cast<std::size_t>(k + 1)].accel - (*states)[static_cast<std::size_t>(k - 1)].accel) /
                 span;
      }
    }
  }
}

// The PR compensation the data's controller applied, against the signed PR model.
void ClassifyAppliedPr(const Samples& samples, Design* d) {
  double cp = 0.0, pp = 0.0, cc = 0.0, unsigned_misfit = 0.0;
  for (std::size_t k = 0; k < samples.states.size(); ++k) {
    const Vector6& c = samples.states[k].compensation;
    const Vector6& pr = samples.commanded_pr_signed[k];
    cp += c.dot(pr), pp += pr.squaredNorm(), cc += c.squaredNorm();
    unsigned_misfit += (c - samples.commanded_pr_unsigned[k]).squaredNorm();
  }
  d->applied_pr_ratio = pp > 0.0 ? cp / pp : 0.0;
  const double misfit = cc - 2.0 * d->applied_pr_ratio * cp + d->applied_pr_ratio * d->applied_pr_ratio * pp;
  if (cc <= 1e-6 * std::max(pp, 1e-30))
    d->applied_pr = PrMode::kNone;
  else if (misfit <= 1e-4 * cc && std::abs(d->applied_pr_ratio - 1.0) < 1e-3)
    d->applied_pr = PrMode::kSigned;
  else if (unsigned_misfit <= 1e-4 * cc)
    d->applied_pr = PrMode::kUnsigned;  // the paper's Eq. (9)
  else
    d->applied_pr = std::nullopt;
}

// Pass 2: the frame estimate, then the linear columns around it.
void FillColumns(const PlatformModel& model, const Samples& samples, Design* d) {
  EstimateFrame(samples.model_points, samples.measured, &d->R0, &d->t0);
  d->model_point = samples.model_points;
  const int n = static_cast<int>(samples.states.size());
  d->point_per_leg.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const std::size_t s = static_cast<std::size_t>(k);
    const Eigen::Matrix<double, 3, 6> RG = d->R0 * samples.G[s];
    // About the encoders' pose the legs' shortfall is put back to first
    // order, for servo_lag to explain as the drives'.
    d->residual.segment<3>(3 * k) =
        samples.measured[s] - (d->R0 * samples.model_points[s] + d->t0) + RG * samples.behind[s];
    d->columns.block<3, 3>(3 * k, 0) = Matrix3::Identity();
    d->columns.block<3, 3>(3 * k, 3) = -d->R0 * calibration::Skew(samples.model_points[s]);
    d->point_per_leg[s] = RG;
    for (Effect e : AllEffects()) {
      const ColumnRange& range = d->Of(e);
      d->columns.block(3 * k, range.begin, 3, range.count) =
          RG * calibration::LegErrorBasis(e, samples.states[s], model);
    }
  }
}

// The drives' following error as the encoders recorded it (leg_cmd −
// leg_enc), split in two: the part servo_lag's terms describe (each leg's
// velocity and acceleration, the legs' jerk alike: leg_error_model.cpp),
// fitted to the encoders alone, stays in the residual for servo_lag to
// explain and size; the rest (a soft loop ringing after each change of
// acceleration, a load it has not yet caught up with) is taken out of the
// residual as measured, where it stands above the tracker's noise. That part
// is the drives' own, sample by sample: no effect of the platform can
// explain it, and left in, a ringing loop is taken for a swaying structure.
void TakeOutWhatTheLagTermsCannot(const std::vector<calibration::LegErrorState>& states, Design* d) {
  if (!d->has_encoder) return;
  constexpr int kTerms = 13;  // 6 velocity, 6 acceleration, 1 jerk
  const auto terms = [&](std::size_t s, int leg) {
    Eigen::Matrix<double, kTerms, 1> x = Eigen::Matrix<double, kTerms, 1>::Zero();
    x(leg) = states[s].velocity(leg);
    x(6 + leg) = states[s].accel(leg);
    x(12) = states[s].jerk(leg);
    return x;
  };
  Eigen::Matrix<double, kTerms, kTerms> gram = Eigen::Matrix<double, kTerms, kTerms>::Zero();
  Eigen::Matrix<double, kTerms, 1> rhs = Eigen::Matrix<double, kTerms, 1>::Zero();
  for (std::size_t s = 0; s < states.size(); ++s) {
    for (int leg = 0; leg < 6; ++leg) {
      const Eigen::Matrix<double, kTerms, 1> x = terms(s, leg);
      gram += x * x.transpose();
      rhs += x * d->servo_error_m[s](leg);
    }
  }
  // A term never excited (a leg at rest all session) is left at zero.
  for (int k = 0; k < kTerms; ++k) {
    if (gram(k, k) <= 0.0) gram(k, k) = 1.0;
  }
  const Eigen::Matrix<double, kTerms, 1> lag = gram.ldlt().solve(rhs);
  std::vector<Vector6> described(states.size());
  double rest2 = 0.0, described2 = 0.0;
  for (std::size_t s = 0; s < states.size(); ++s) {
    for (int leg = 0; leg < 6; ++leg) described[s](leg) = terms(s, leg).dot(lag);
    rest2 += (d->point_per_leg[s] * (d->servo_error_m[s] - described[s])).squaredNorm();
    described2 += (d->point_per_leg[s] * described[s]).squaredNorm();
  }
  const double n = std::max<double>(1.0, static_cast<double>(states.size()));
  d->drives_rest_rms_m = std::sqrt(rest2 / n);
  d->drives_described_rms_m = std::sqrt(described2 / n);
  // Under the tracker's noise the rest cannot pass for structure: it is left
  // where it is, for servo_lag's terms to take up what they can of it as the
  // drives' (a stiff loop's rest lies far under the noise).
  const double sigma_axis = NoiseFloorRms(*d) / std::sqrt(3.0);
  d->drives_rest_taken_out = d->drives_rest_rms_m > sigma_axis;
  if (!d->drives_rest_taken_out) return;
  for (std::size_t s = 0; s < states.size(); ++s) {
    d->residual.segment<3>(3 * static_cast<Eigen::Index>(s)) +=
        d->point_per_leg[s] * (d->servo_error_m[s] - described[s]);
    d->servo_error_m[s] = described[s];
  }
}

}  // namespace

double NoiseFloorRms(const Design& d) {
  std::vector<double> diffs, all;
  for (const ColumnRange& run : d.run_samples) {
    for (int k = run.begin + 1; k < run.begin + run.count; ++k) {
      const bool rest = d.leg_velocity_m_s[static_cast<std::size_t>(k)].cwiseAbs().maxCoeff() < 1e-5 &&
                        d.leg_velocity_m_s[static_cast<std::size_t>(k - 1)].cwiseAbs().maxCoeff() < 1e-5;
      for (int axis = 0; axis < 3; ++axis) {
        const double diff = d.residual(3 * k + axis) - d.residual(3 * (k - 1) + axis);
        all.push_back(std::abs(diff));
        if (rest) diffs.push_back(std::abs(diff));
      }
    }
  }
  std::vector<double>& use = diffs.size() >= 150 ? diffs : all;
  if (use.empty()) return 0.0;
  std::nth_element(use.begin(), use.begin() + static_cast<std::ptrdiff_t>(use.size() / 2), use.end());
  const double mad = use[use.size() / 2];
  // |a − b| of two N(0, σ²) samples has median 0.6745·√2·σ.
  const double sigma = mad / (0.6745 * std::sqrt(2.0));
  return std::sqrt(3.0) * sigma;
}

Design BuildDesign(const PlatformModel& model, const MeasurementData& data, const DesignOptions& o) {
  Design d;
  d.runs = data.runs;
  LayOutColumns(static_cast<int>(data.rows.size()), &d);
  d.has_encoder = !data.rows.empty();
  for (const MeasurementRow& row : data.rows) d.has_encoder = d.has_encoder && row.has_encoder;
  Samples samples = TrackSamples(model, data, o, &d);
  AddJerk(d, &samples.states);
  ClassifyAppliedPr(samples, &d);
  FillColumns(model, samples, &d);
  TakeOutWhatTheLagTermsCannot(samples.states, &d);
  return d;
}

Eigen::VectorXd ResidualWhereTheLegsStood(const Design& d) {
  Eigen::VectorXd r = d.residual;
  if (!d.has_encoder) return r;
  for (int k = 0; k < d.samples(); ++k) {
    const std::size_t s = static_cast<std::size_t>(k);
    r.segment<3>(3 * k) += d.point_per_leg[s] * d.servo_error_m[s];
  }
  return r;
}

const char* AppliedPrName(const std::optional<PrMode>& applied) { return applied ? PrModeName(*applied) : "other"; }

}  // namespace edsp::gap
