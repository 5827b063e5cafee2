// The discretised transfer functions against their closed-form responses.
#include "edsp/cueing/linear_filter.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "thrown_message.h"

namespace edsp {
namespace {

using test_support::ThrownMessage;

// The output at t = k·T of a unit step applied from t = 0 (output k of Step).
std::vector<double> StepResponse(const TransferFunction& tf, double period_s, int samples) {
  DiscreteFilter filter(tf, period_s);
  std::vector<double> out;
  for (int k = 0; k < samples; ++k) out.push_back(filter.Step(1.0));
  return out;
}

TEST(LinearFilter, AFirstOrderLagIsItsExponentialAtEverySample) {
  const double tau = 0.66, period = 1e-3;
  const auto y = StepResponse({{1.0}, {tau, 1.0}}, period, 3000);
  for (int k = 0; k < 3000; k += 37) EXPECT_NEAR(y[k], 1.0 - std::exp(-k * period / tau), 1e-12) << k;
}

TEST(LinearFilter, AnUnderdampedSecondOrderHighPassIsItsClosedForm) {
  // s² / (s² + 2ζω s + ω²): e^{−ζωt} (cos ωd t − ζ/√(1−ζ²) sin ωd t).
  const double w = 4.0, zeta = 0.3, period = 2e-3;
  const double wd = w * std::sqrt(1.0 - zeta * zeta);
  const auto y = StepResponse({{1.0, 0.0, 0.0}, {1.0, 2.0 * zeta * w, w * w}}, period, 2000);
  for (int k = 0; k < 2000; k += 23) {
    const double t = k * period;
    const double expected =
        std::exp(-zeta * w * t) * (std::cos(wd * t) - zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t));
    EXPECT_NEAR(y[k], expected, 1e-11) << "t = " << t;
  }
}

TEST(LinearFilter, AStiffModelIsExactAtAPeriodLongerThanItsFastestTimeConstant) {
  // 1/((τ1 s+1)(τ2 s+1)) with τ2 = 5 ms sampled at 10 ms: still exact.
  const double t1 = 5.73, t2 = 0.005, period = 0.01;
  const auto y = StepResponse({{1.0}, {t1 * t2, t1 + t2, 1.0}}, period, 1000);
  for (int k = 0; k < 1000; k += 11) {
    const double t = k * period;
    const double expected = 1.0 - (t1 * std::exp(-t / t1) - t2 * std::exp(-t / t2)) / (t1 - t2);
    EXPECT_NEAR(y[k], expected, 1e-12) << "t = " << t;
  }
}

TEST(LinearFilter, ResetToAConstantInputHoldsItsSteadyState) {
  // (13.2 s + 1)/((5.33 s + 1)(0.66 s + 1)): DC gain 1.
  DiscreteFilter filter({{13.2, 1.0}, {5.33 * 0.66, 5.33 + 0.66, 1.0}}, 1e-3);
  filter.Reset(9.80665);
  for (int k = 0; k < 5000; ++k) ASSERT_NEAR(filter.Step(9.80665), 9.80665, 1e-9) << k;
}

TEST(LinearFilter, SeriesMultipliesNumeratorsAndDenominators) {
  const TransferFunction g = Series({{2.0, 0.0}, {1.0, 3.0}}, {{1.0}, {1.0, 1.0, 5.0}});
  EXPECT_EQ(g.numerator, (std::vector<double>{2.0, 0.0}));
  EXPECT_EQ(g.denominator, (std::vector<double>{1.0, 4.0, 8.0, 15.0}));
}

TEST(LinearFilter, ABadTransferFunctionIsRefusedWithWhatIsWrong) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(ThrownMessage<std::invalid_argument>([] {
              DiscreteFilter({{1.0, 0.0, 0.0}, {1.0, 1.0}}, 1e-3);
            }).find("not proper"),
            std::string::npos);
  EXPECT_NE(ThrownMessage<std::invalid_argument>([] {
              DiscreteFilter({{1.0}, {0.0, 1.0}}, 1e-3);
            }).find("leading denominator coefficient"),
            std::string::npos);
  EXPECT_NE(ThrownMessage<std::invalid_argument>([nan] {
              DiscreteFilter({{nan}, {1.0, 1.0}}, 1e-3);
            }).find("not finite"),
            std::string::npos);
  EXPECT_NE(ThrownMessage<std::invalid_argument>([] {
              DiscreteFilter({{1.0}, {1.0, 1.0}}, 0.0);
            }).find("period 0"),
            std::string::npos);
}

TEST(LinearFilter, DescribeWritesThePolynomials) {
  EXPECT_EQ(Describe({{13.2, 1.0}, {3.5178, 5.99, 1.0}}), "(13.2 s + 1) / (3.5178 s^2 + 5.99 s + 1)");
  EXPECT_EQ(Describe({{1.0, 0.0, 0.0}, {1.0, -2.0, 4.0}}), "(s^2) / (s^2 - 2 s + 4)");
}

}  // namespace
}  // namespace edsp
