#include "edsp/diagnosis/parameter_table.h"

#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace edsp::gap {

namespace {

constexpr const char* kAxes[] = {"x", "y", "z"};

double At(const Eigen::VectorXd& v, int k) { return k < v.size() ? v(k) : std::nan(""); }

// Value k of a group in its unit, with its σ (none for a polar pair's).
std::string Cell(const EffectResult& r, const ParameterGroup& g, int k) {
  const int at = calibration::ThetaIndex(g, k);
  const double value = at < r.theta.size() ? calibration::GroupValue(g, r.theta.data(), k) : std::nan("");
  const double sigma = calibration::HasSigma(g) ? At(r.sigma, at) * std::abs(g.unit_scale) : std::nan("");
  return ValueWithSigma(value * g.unit_scale, sigma, g.decimals);
}

// One column a value per leg: "offset (µm)", "base x (µm)".
struct LegColumn {
  std::string header;
  const ParameterGroup* group;
  int axis;
};

std::vector<LegColumn> LegColumns(const std::vector<ParameterGroup>& groups) {
  std::vector<LegColumn> columns;
  for (const ParameterGroup& g : groups) {
    if (!calibration::IsPerLeg(g)) continue;
    if (calibration::ValuesPerLeg(g) == 1) {
      columns.push_back({fmt::format("{} ({})", g.label, g.unit), &g, 0});
      continue;
    }
    for (int axis = 0; axis < 3; ++axis)
      columns.push_back({fmt::format("{} {} ({})", g.label, kAxes[axis], g.unit), &g, axis});
  }
  return columns;
}

std::string LegTable(const EffectResult& r, const std::vector<LegColumn>& columns) {
  std::string t = "| leg |";
  std::string rule = "|---|";
  for (const LegColumn& c : columns) t += fmt::format(" {} |", c.header), rule += "---|";
  t += "\n" + rule + "\n";
  for (int leg = 0; leg < 6; ++leg) {
    t += fmt::format("| {} |", leg + 1);
    for (const LegColumn& c : columns) {
      t += " " + Cell(r, *c.group, calibration::ValuesPerLeg(*c.group) * leg + c.axis) + " |";
    }
    t += "\n";
  }
  return t;
}

// The platform-wide values, a row each ("c.o.m. moment term x").
std::string ScalarTable(const EffectResult& r, const std::vector<ParameterGroup>& groups) {
  std::string t;
  for (const ParameterGroup& g : groups) {
    if (calibration::IsPerLeg(g)) continue;
    const int count = calibration::ValueCount(g);
    for (int k = 0; k < count; ++k) {
      const std::string name = count == 1 ? g.label : fmt::format("{} {}", g.label, kAxes[k]);
      t += fmt::format("| {} | {} | {} |\n", name, Cell(r, g, k), g.unit);
    }
  }
  return t.empty() ? t : "| parameter | value | unit |\n|---|---|---|\n" + t;
}

}  // namespace

std::string ValueWithSigma(double value, double sigma, int decimals) {
  if (!std::isfinite(value)) return "–";
  if (!std::isfinite(sigma) || sigma <= 0.0) return fmt::format("{:.{}f}", value, decimals);
  return fmt::format("{:.{}f} ± {:.{}f}", value, decimals, sigma, decimals);
}

std::string ParameterTableMarkdown(const EffectResult& r) {
  if (r.theta.size() == 0) return "";
  const std::vector<ParameterGroup> groups = ParameterGroups(r.effect);
  const std::vector<LegColumn> columns = LegColumns(groups);
  const std::string scalars = ScalarTable(r, groups);
  std::string md =
      fmt::format("### `{}`: {} ({})\n\n", EffectName(r.effect), EffectTitle(r.effect), VerdictName(r.verdict));
  if (!columns.empty()) md += LegTable(r, columns);
  if (!columns.empty() && !scalars.empty()) md += "\n";
  return md + scalars;
}

}  // namespace edsp::gap
