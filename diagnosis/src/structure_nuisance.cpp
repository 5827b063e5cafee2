#include "edsp/diagnosis/structure_nuisance.h"

#include <algorithm>
#include <cmath>

#include "edsp/kinematics/structural_mode.h"

namespace edsp::gap {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// A's acceleration at each sample of a run in {B}: central differences of
// the model's point along the commands (none at the run's ends).
std::vector<Vector3> PointAcceleration(const Design& d, const ColumnRange& run) {
  std::vector<Vector3> a(static_cast<std::size_t>(run.count), Vector3::Zero());
  for (int k = 1; k + 1 < run.count; ++k) {
    const std::size_t i = static_cast<std::size_t>(run.begin + k);
    const double h1 = d.time_s[i] - d.time_s[i - 1], h2 = d.time_s[i + 1] - d.time_s[i];
    if (!(h1 > 0.0 && h2 > 0.0)) continue;
    const Vector3 v1 = (d.model_point[i] - d.model_point[i - 1]) / h1;
    const Vector3 v2 = (d.model_point[i + 1] - d.model_point[i]) / h2;
    a[static_cast<std::size_t>(k)] = (v2 - v1) / (0.5 * (h1 + h2));
  }
  return a;
}

// The mode's response at unit gain (structural_mode.h) at every sample, in
// the order of the design's samples and carried from run to run as the
// leg-error model's is (design.cpp), so that these columns are the
// structural_resonance effect's at the same frequency and damping.
std::vector<Vector3> ModeResponse(const Design& d, double hz, double zeta) {
  std::vector<Vector3> x(static_cast<std::size_t>(d.samples()), Vector3::Zero());
  StructuralMode mode(hz, zeta);
  double last_t = 0.0;
  for (const ColumnRange& run : d.run_samples) {
    const std::vector<Vector3> accel = PointAcceleration(d, run);
    for (int k = 0; k < run.count; ++k) {
      const std::size_t i = static_cast<std::size_t>(run.begin + k);
      x[i] = mode.Advance(d.time_s[i] - last_t, accel[static_cast<std::size_t>(k)]);
      last_t = d.time_s[i];
    }
  }
  return x;
}

}  // namespace

std::vector<double> CandidateModeFrequencies(const ResidualStructure& structure) {
  std::vector<double> hz = {1.5, 2.5, 4.0, 6.0, 9.0, 13.0};
  if (structure.dominant_hz > 1.0) hz.push_back(structure.dominant_hz);
  return hz;
}

Eigen::MatrixXd SwayColumns(const Design& d, double hz, double zeta) {
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(3 * d.samples(), 3);
  const std::vector<Vector3> sway = ModeResponse(d, hz, zeta);
  for (int n = 0; n < d.samples(); ++n) {
    for (int axis = 0; axis < 3; ++axis) c.block<3, 1>(3 * n, axis) = d.R0.col(axis) * sway[static_cast<std::size_t>(n)](axis);
  }
  return c;
}

Eigen::MatrixXd StructureColumns(const Design& d, double hz, double zeta) {
  const double omega = kTwoPi * hz;
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(3 * d.samples(), 9);
  c.leftCols(3) = SwayColumns(d, hz, zeta);
  for (int n = 0; n < d.samples(); ++n) {
    const double t = d.time_s[static_cast<std::size_t>(n)];
    for (int axis = 0; axis < 3; ++axis) {
      c(3 * n + axis, 3 + axis) = std::sin(omega * t);
      c(3 * n + axis, 6 + axis) = std::cos(omega * t);
    }
  }
  return c;
}

Design WithoutColumns(const Design& d) {
  Design out;
  out.residual = d.residual;
  out.frame = d.frame;
  out.effect = d.effect;
  out.sample_run = d.sample_run;
  out.run_samples = d.run_samples;
  out.runs = d.runs;
  out.source_row = d.source_row;
  out.point_per_leg = d.point_per_leg;
  out.model_point = d.model_point;
  out.leg_velocity_m_s = d.leg_velocity_m_s;
  out.leg_accel_m_s2 = d.leg_accel_m_s2;
  out.servo_error_m = d.servo_error_m;
  out.time_s = d.time_s;
  out.displacement = d.displacement;
  out.has_encoder = d.has_encoder;
  out.applied_pr_ratio = d.applied_pr_ratio;
  out.applied_pr = d.applied_pr;
  out.R0 = d.R0;
  out.t0 = d.t0;
  return out;
}

Design WithNuisance(const Design& d, const Eigen::MatrixXd& extra) {
  Design out = WithoutColumns(d);
  const int m = static_cast<int>(extra.cols()), first = d.frame.begin + d.frame.count + d.nuisance.count;
  const Eigen::Index rest = d.columns.cols() - first;
  out.columns.resize(d.columns.rows(), d.columns.cols() + m);
  out.columns.leftCols(first) = d.columns.leftCols(first);
  out.columns.middleCols(first, m) = extra;
  out.columns.rightCols(rest) = d.columns.rightCols(rest);
  out.nuisance = {d.nuisance.count > 0 ? d.nuisance.begin : first, d.nuisance.count + m};
  for (ColumnRange& r : out.effect) r.begin += m;
  return out;
}

}  // namespace edsp::gap
