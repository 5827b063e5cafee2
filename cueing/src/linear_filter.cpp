#include "edsp/cueing/linear_filter.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <unsupported/Eigen/MatrixFunctions>

namespace edsp {
namespace {

void CheckCoefficients(const TransferFunction& tf, double period_s) {
  if (!(period_s > 0.0) || !std::isfinite(period_s)) {
    throw std::invalid_argument(fmt::format("filter period {} s: must be finite and > 0", period_s));
  }
  if (tf.denominator.empty() || tf.denominator.front() == 0.0) {
    throw std::invalid_argument(
        fmt::format("G(s) = {}: the leading denominator coefficient must not be 0", Describe(tf)));
  }
  if (tf.numerator.empty() || tf.numerator.size() > tf.denominator.size()) {
    throw std::invalid_argument(fmt::format("G(s) = {}: not proper (numerator of higher degree)", Describe(tf)));
  }
  for (const auto* coefficients : {&tf.numerator, &tf.denominator}) {
    for (double c : *coefficients) {
      if (!std::isfinite(c))
        throw std::invalid_argument(fmt::format("G(s) = {}: a coefficient is not finite", Describe(tf)));
    }
  }
}

std::string Polynomial(const std::vector<double>& coefficients) {
  std::string text;
  const int degree = static_cast<int>(coefficients.size()) - 1;
  for (int i = 0; i <= degree; ++i) {
    const double c = coefficients[static_cast<std::size_t>(i)];
    if (c == 0.0 && degree > 0) continue;
    const int power = degree - i;
    if (!text.empty())
      text += c < 0.0 ? " - " : " + ";
    else if (c < 0.0)
      text += "-";
    const double magnitude = std::fabs(c);
    if (power == 0 || magnitude != 1.0) text += fmt::format("{:g}", magnitude);
    if (power >= 1)
      text += power == 1 ? (magnitude != 1.0 ? " s" : "s") : fmt::format("{}s^{}", magnitude != 1.0 ? " " : "", power);
  }
  return text.empty() ? "0" : text;
}

}  // namespace

std::string Describe(const TransferFunction& tf) {
  return fmt::format("({}) / ({})", Polynomial(tf.numerator), Polynomial(tf.denominator));
}

TransferFunction Series(const TransferFunction& g1, const TransferFunction& g2) {
  auto multiply = [](const std::vector<double>& p, const std::vector<double>& q) {
    if (p.empty() || q.empty()) return std::vector<double>{};
    std::vector<double> r(p.size() + q.size() - 1, 0.0);
    for (std::size_t i = 0; i < p.size(); ++i) {
      for (std::size_t j = 0; j < q.size(); ++j) r[i + j] += p[i] * q[j];
    }
    return r;
  };
  return {multiply(g1.numerator, g2.numerator), multiply(g1.denominator, g2.denominator)};
}

StateSpace Realise(const TransferFunction& tf) {
  CheckCoefficients(tf, 1.0);
  const int order = static_cast<int>(tf.denominator.size()) - 1;
  const double a0 = tf.denominator.front();
  // The numerator padded to the denominator's length, both made monic.
  std::vector<double> b(tf.denominator.size(), 0.0);
  std::copy(tf.numerator.begin(), tf.numerator.end(), b.end() - static_cast<long>(tf.numerator.size()));
  StateSpace ss;
  ss.d = b[0] / a0;
  // Controllable canonical form of the strictly proper rest.
  ss.a = Eigen::MatrixXd::Zero(order, order);
  ss.b = Eigen::VectorXd::Zero(order);
  ss.c = Eigen::RowVectorXd::Zero(order);
  for (int i = 0; i + 1 < order; ++i) ss.a(i, i + 1) = 1.0;
  for (int i = 1; i <= order; ++i) {
    const double ai = tf.denominator[static_cast<std::size_t>(i)] / a0;
    ss.a(order - 1, order - i) = -ai;
    ss.c(order - i) = b[static_cast<std::size_t>(i)] / a0 - ss.d * ai;
  }
  if (order > 0) ss.b(order - 1) = 1.0;
  return ss;
}

HeldSystem ZeroOrderHold(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double period_s) {
  // exp([[A, B], [0, 0]]·T) = [[Ad, Bd], [0, I]].
  const Eigen::Index n = a.rows(), m = b.cols();
  Eigen::MatrixXd augmented = Eigen::MatrixXd::Zero(n + m, n + m);
  augmented.topLeftCorner(n, n) = a * period_s;
  augmented.topRightCorner(n, m) = b * period_s;
  const Eigen::MatrixXd held = augmented.exp();
  return {held.topLeftCorner(n, n), held.topRightCorner(n, m)};
}

DiscreteFilter::DiscreteFilter(const TransferFunction& tf, double period_s) : period_s_(period_s) {
  CheckCoefficients(tf, period_s);
  const StateSpace ss = Realise(tf);
  const auto order = static_cast<int>(ss.a.rows());
  const Eigen::MatrixXd& a = ss.a;
  const Eigen::VectorXd& input = ss.b;
  c_ = ss.c;
  d_ = ss.d;
  const HeldSystem held = ZeroOrderHold(a, input, period_s);
  a_ = held.ad;
  b_ = held.bd.col(0);
  x_ = Eigen::VectorXd::Zero(order);
  // A pole at s = 0 has no steady state for a constant input: left at zero.
  const Eigen::MatrixXd settle = Eigen::MatrixXd::Identity(order, order) - a_;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(settle);
  steady_per_unit_ = lu.isInvertible() ? Eigen::VectorXd(lu.solve(b_)) : Eigen::VectorXd::Zero(order);
}

double DiscreteFilter::Step(double input) {
  const double output = (c_.size() > 0 ? (c_ * x_).value() : 0.0) + d_ * input;
  if (x_.size() > 0) x_ = a_ * x_ + b_ * input;
  return output;
}

void DiscreteFilter::Reset(double input) { x_ = steady_per_unit_ * input; }

}  // namespace edsp
