#include "edsp/diagnosis/percent_text.h"

#include <cmath>

#include <fmt/format.h>

namespace edsp::gap {

namespace {

// A fraction under 0.05% in size prints as 0.0%.
constexpr double kRoundsToZero = 0.0005;

}  // namespace

std::string Percent(double fraction) {
  return fmt::format("{:.1f}%", std::abs(fraction) < kRoundsToZero ? 0.0 : 100 * fraction);
}

std::string HeldOutChange(double cv_gain) {
  if (std::abs(cv_gain) < kRoundsToZero) return "no better";
  return Percent(std::abs(cv_gain)) + (cv_gain > 0.0 ? " better" : " worse");
}

}  // namespace edsp::gap
