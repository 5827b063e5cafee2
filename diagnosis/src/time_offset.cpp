#include "edsp/diagnosis/time_offset.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "edsp/diagnosis/linear_fit.h"
#include "edsp/diagnosis/structure_nuisance.h"

namespace edsp::gap {

namespace {

// −Ȧ per sample (3 rows each): what a reading δ late adds per second of δ.
Eigen::MatrixXd OffsetColumn(const Design& d) {
  Eigen::MatrixXd c(3 * d.samples(), 1);
  for (int k = 0; k < d.samples(); ++k) {
    const std::size_t s = static_cast<std::size_t>(k);
    c.block<3, 1>(3 * k, 0) = -(d.point_per_leg[s] * d.leg_velocity_m_s[s]);
  }
  return c;
}

std::vector<Effect> AllButServoLag() {
  std::vector<Effect> effects;
  for (Effect e : AllEffects()) {
    if (e != Effect::kServoLag) effects.push_back(e);
  }
  return effects;
}

}  // namespace

TimeOffset EstimateTimeOffset(const Design& design, const Eigen::VectorXd& prior_weight) {
  TimeOffset out;
  if (!design.has_encoder || design.samples() == 0) {
    out.note =
        "not estimated: without encoder columns a clock offset and a servo lag equal on every leg are one "
        "(a selected servo_lag is checked against an offset instead)";
    return out;
  }
  Design e = WithNuisance(design, OffsetColumn(design));
  // The drives' own tracking error set aside: what is left of a servo lag
  // is nothing, of a clock offset all of it.
  e.residual = ResidualWhereTheLegsStood(design);
  const int offset_column = design.frame.begin + design.frame.count + design.nuisance.count;
  Eigen::VectorXd prior(e.parameters());
  prior << prior_weight.head(offset_column), 0.0, prior_weight.tail(prior_weight.size() - offset_column);

  const Coefficient offset =
      FitCoefficient(e, GramSet(e, MakeFolds(e)), ColumnsOf(e, AllButServoLag()), offset_column, prior);
  out.estimated = true;
  out.offset_s = offset.value;
  out.sigma_s = offset.sigma;
  out.applied = std::abs(out.offset_s) > kTimeOffsetSignificance * out.sigma_s;
  out.note = out.applied ? fmt::format(
                               "the tracker's clock runs {} (its readings {} than their stamps say; from the "
                               "encoder columns); removed like the frame",
                               ClockAhead(out.offset_s, out.sigma_s), out.offset_s > 0.0 ? "older" : "newer")
                         : fmt::format("the clocks agree within the data's resolution ({:+.3f} ms ± {:.3f})",
                                       out.offset_s * 1e3, out.sigma_s * 1e3);
  return out;
}

std::string ClockAhead(double offset_s, double sigma_s) {
  return fmt::format("{:.3f} ms ± {:.3f} {} the controller's", std::abs(offset_s) * 1e3, sigma_s * 1e3,
                     offset_s > 0.0 ? "ahead of" : "behind");
}

void RemoveTimeOffset(double offset_s, Design* design) { design->residual -= offset_s * OffsetColumn(*design); }

Eigen::MatrixXd DriftingOffsetColumns(const Design& d) {
  Eigen::MatrixXd c(3 * d.samples(), 2);
  c.col(0) = OffsetColumn(d);
  if (d.samples() == 0) return c;
  const double t0 = *std::min_element(d.time_s.begin(), d.time_s.end());
  for (int k = 0; k < d.samples(); ++k) {
    c.block<3, 1>(3 * k, 1) = c.block<3, 1>(3 * k, 0) * (d.time_s[static_cast<std::size_t>(k)] - t0);
  }
  return c;
}

}  // namespace edsp::gap
