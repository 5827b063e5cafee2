#include "edsp/diagnosis/structure_nuisance.h"

#include <algorithm>
#include <cmath>

#include "edsp/kinematics/structural_mode.h"

namespace edsp::gap {

namespace {

// The mode's response at unit gain (structural_mode.h) at every sample, in
// the order of the design's samples and carried from run to run as the
// leg-error model's is (design.cpp), so that these columns are the
// structural_resonance effect's at the same frequency and damping.
std::vector<Vector3> ModeResponse(const Design& d, double hz, double zeta) {
  std::vector<Vector3> x(static_cast<std::size_t>(d.samples()), Vector3::Zero());
  StructuralMode mode(hz, zeta);
  double last_t = 0.0;
  for (const ColumnRange& run : d.run_samples) {
    for (int k = 0; k < run.count; ++k) {
      const std::size_t i = static_cast<std::size_t>(run.begin + k);
      x[i] = mode.Advance(d.time_s[i] - last_t, d.point_accel_m_s2[i]);
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
    for (int axis = 0; axis < 3; ++axis)
      c.block<3, 1>(3 * n, axis) = d.R0.col(axis) * sway[static_cast<std::size_t>(n)](axis);
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

Eigen::MatrixXd BaseTiltColumns(const Design& d) {
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(3 * d.samples(), 24);
  for (int n = 0; n < d.samples(); ++n) {
    const std::size_t s = static_cast<std::size_t>(n);
    const Vector3& A = d.model_point[s];
    int column = 0;
    for (int m = 0; m < 4; ++m) {
      const Vector3 M = d.load_moment_per_kg[s].col(m);
      for (int i = 0; i < 3; ++i) {
        for (int j = i; j < 3; ++j, ++column) {
          Vector3 tilt = Vector3::Zero();
          tilt(i) += M(j);
          if (j != i) tilt(j) += M(i);
          c.block<3, 1>(3 * n, column) = d.R0 * tilt.cross(A);
        }
      }
    }
  }
  return c;
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
