#pragma once
// A continuous transfer function run on a sampled signal: the washout's
// filters and the vestibular models are all written as G(s) in the
// literature, so they are given that way and discretised here exactly for
// a zero-order-held input (the matrix exponential of the state-space
// realisation), whatever the ratio of their time constants to the period.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace edsp {

// G(s) = (b0 sⁿ + … + bn) / (a0 sᵐ + … + am), coefficients in descending
// powers of s; proper (n ≤ m), a0 ≠ 0.
struct TransferFunction {
  std::vector<double> numerator;
  std::vector<double> denominator;
};

// G(s) as text, for error messages: "(13.2 s + 1) / (3.52 s^2 + 5.99 s + 1)".
std::string Describe(const TransferFunction& tf);

// The product G1(s)·G2(s).
TransferFunction Series(const TransferFunction& g1, const TransferFunction& g2);

// G(s) as x' = a x + b u, y = c x + d u: its controllable canonical
// realisation. Throws std::invalid_argument as DiscreteFilter does.
struct StateSpace {
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  Eigen::RowVectorXd c;
  double d = 0.0;
};
StateSpace Realise(const TransferFunction& tf);

// x' = a x + b u sampled every `period_s` with u held between samples:
// x[k+1] = ad x[k] + bd u[k], exactly (the matrix exponential).
struct HeldSystem {
  Eigen::MatrixXd ad;
  Eigen::MatrixXd bd;
};
HeldSystem ZeroOrderHold(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double period_s);

class DiscreteFilter {
 public:
  // Throws std::invalid_argument naming what is wrong (improper, a0 = 0,
  // a coefficient not finite, period ≤ 0).
  DiscreteFilter(const TransferFunction& tf, double period_s);

  // The output for this sample's input (held until the next).
  double Step(double input);
  // Back to rest, or to the steady state of a constant input (for a
  // signal that has been at `input` forever: gravity in the otoliths).
  void Reset(double input = 0.0);
  double period_s() const { return period_s_; }

 private:
  double period_s_;
  Eigen::MatrixXd a_;  // x[k+1] = a x[k] + b u[k]
  Eigen::VectorXd b_;
  Eigen::RowVectorXd c_;  // y[k] = c x[k] + d u[k]
  double d_ = 0.0;
  Eigen::VectorXd x_;
  Eigen::VectorXd steady_per_unit_;  // the state a unit constant input settles to
};

}  // namespace edsp
