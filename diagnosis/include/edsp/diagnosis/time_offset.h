#pragma once
// The tracker's clock against the controller's: a nuisance estimated like
// the frame, reported and removed from the residual, never an effect.
//
// A reading stamped t but taken at t − δ is off by −δ·Ȧ, the signature of a
// servo lag equal on every leg: from the tracker alone the two are one. The
// encoders part them: a drive's lag lies between the command and the motor,
// which the encoders read, while a clock offset lies between the tracker and
// everything else. So δ is estimated on the residual with the encoders'
// servo error taken out, beside every effect but servo_lag; without encoder
// columns it is not estimated, and the report says why. A clock that
// drifts over the session is not removed: the clock check tests it
// as something beyond the vocabulary (DriftingOffsetColumns, beyond_vocabulary.h).

#include <string>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

struct TimeOffset {
  bool estimated = false;  // the data has encoder columns
  double offset_s = 0.0;   // δ: how late the readings are (a row stamped t reads t − δ: the tracker's clock ahead)
  double sigma_s = 0.0;    // 1-σ, from the fit's covariance
  bool applied = false;    // |δ| > kTimeOffsetSignificance·σ: removed from the residual
  std::string note;        // for the report, one sentence
};

inline constexpr double kTimeOffsetSignificance = 5.0;

// δ from `design`; `prior_weight` is the effects' ridge (per design column,
// as for the diagnosis's own fits).
TimeOffset EstimateTimeOffset(const Design& design, const Eigen::VectorXd& prior_weight);

// "3.001 ms ± 0.001 ahead of the controller's" (behind for δ < 0): how the
// report and the notes name a clock offset.
std::string ClockAhead(double offset_s, double sigma_s);

// The design's residual as if the tracker's clock were the controller's.
void RemoveTimeOffset(double offset_s, Design* design);

// A tracker clock running free of the controller's: readings late by
// δ₀ + ρ·(t − t₀), t₀ the session's first sample, ρ the clock's gain (s/s).
// Two columns (3 rows per sample): −Ȧ and −Ȧ·(t − t₀), per second of δ₀
// and per unit of ρ. A drive's lag is the same in every run; a drifting
// clock's grows with the session, which is what parts the two without
// encoders (beyond_vocabulary.h's clock check).
Eigen::MatrixXd DriftingOffsetColumns(const Design& design);

}  // namespace edsp::gap
