#include "edsp/diagnosis/parameter_table.h"

#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace edsp::gap {

namespace {

constexpr double kGravity = 9.80665;      // m/s² per g
constexpr double kPi = 3.14159265358979323846;

// A per-leg column: θ[first + stride·leg] × scale.
struct LegColumn {
  const char* header;
  int first;
  int stride;
  double scale;
  int decimals;
};

// One platform-wide value: offset + θ[index] × scale.
struct Scalar {
  const char* name;
  int index;
  double scale;
  const char* unit;
  int decimals;
  double offset = 0.0;
};

struct Layout {
  const char* title;
  std::vector<LegColumn> legs;
  std::vector<Scalar> scalars;
};

// How each effect's θ reads in engineering units. The SI meaning of each θ
// is the basis of kinematics/leg_error_model.cpp.
Layout LayoutOf(Effect effect) {
  switch (effect) {
    case Effect::kPassiveRotation:
      return {"passive rotation (scale of the signed PR model)",
              {},
              {{"PR the screws follow, × signed model", 0, 1.0, "×", 3},
               {"compensation the data's controller applied, × its mode", 1, 1.0, "×", 3, 1.0}}};
    case Effect::kLegOffset:
      return {"a constant length per leg", {{"offset (µm)", 0, 1, 1e6, 1}}, {}};
    case Effect::kJointPosition:
      return {"joint centres (base in B, platform in M)",
              {{"base x (µm)", 0, 3, 1e6, 1}, {"base y (µm)", 1, 3, 1e6, 1}, {"base z (µm)", 2, 3, 1e6, 1},
               {"platform x (µm)", 18, 3, 1e6, 1}, {"platform y (µm)", 19, 3, 1e6, 1},
               {"platform z (µm)", 20, 3, 1e6, 1}},
              {}};
    case Effect::kLeadError:
      return {"lead error (length per length of stroke)", {{"lead error (ppm)", 0, 1, 1e6, 1}}, {}};
    case Effect::kPeriodicLeadError:
      return {"periodic lead error (once per screw turn)", {}, {}};  // amplitude/phase: PeriodicTable
    case Effect::kBacklash:
      return {"play between the motor and the nut", {{"play (µm)", 0, 1, 1e6, 1}}, {}};
    case Effect::kServoLag:
      return {"the drives' following error",
              {{"velocity lag (ms)", 0, 1, 1e3, 2}, {"acceleration lag (ms²)", 6, 1, 1e6, 2}},
              {{"jerk lag, all legs", 12, 1e9, "ms³", 1}}};
    case Effect::kCompliance:
      return {"leg shortening under the moving mass' load",
              {{"per g of load (µm)", 0, 1, 1e6 * kGravity, 2}},
              {{"c.o.m. moment term x", 6, 1e6 * kGravity, "µm·m per g", 3},
               {"c.o.m. moment term y", 7, 1e6 * kGravity, "µm·m per g", 3},
               {"c.o.m. moment term z", 8, 1e6 * kGravity, "µm·m per g", 3}}};
    case Effect::kThermalDrift:
      return {"thermal drift (screw growth)",
              {},
              {{"with recent travel", 0, 1e6, "µm per m of travel", 2},
               {"with recent travel, per m of stroke", 1, 1e6, "µm per m of travel per m", 2},
               {"with time under power", 2, 3.6e9, "µm per hour", 2},
               {"with time under power, per m of stroke", 3, 3.6e9, "µm per hour per m", 2}}};
  }
  return {"", {}, {}};
}

double At(const Eigen::VectorXd& v, int k) { return k < v.size() ? v(k) : std::nan(""); }

std::string PeriodicTable(const EffectResult& r) {
  std::string t = "| leg | amplitude (µm) | phase (°) |\n|---|---|---|\n";
  for (int i = 0; i < 6; ++i) {
    const double s = At(r.theta, 2 * i), c = At(r.theta, 2 * i + 1);
    t += fmt::format("| {} | {:.1f} | {:.0f} |\n", i + 1, std::hypot(s, c) * 1e6, std::atan2(c, s) * 180.0 / kPi);
  }
  return t;
}

std::string LegTable(const EffectResult& r, const std::vector<LegColumn>& columns) {
  std::string t = "| leg |";
  std::string rule = "|---|";
  for (const LegColumn& c : columns) t += fmt::format(" {} |", c.header), rule += "---|";
  t += "\n" + rule + "\n";
  for (int i = 0; i < 6; ++i) {
    t += fmt::format("| {} |", i + 1);
    for (const LegColumn& c : columns) {
      const int k = c.first + c.stride * i;
      t += " " + ValueWithSigma(At(r.theta, k) * c.scale, At(r.sigma, k) * std::abs(c.scale), c.decimals) + " |";
    }
    t += "\n";
  }
  return t;
}

std::string ScalarTable(const EffectResult& r, const std::vector<Scalar>& scalars) {
  std::string t = "| parameter | value | unit |\n|---|---|---|\n";
  for (const Scalar& s : scalars) {
    t += fmt::format("| {} | {} | {} |\n", s.name,
                     ValueWithSigma(s.offset + At(r.theta, s.index) * s.scale, At(r.sigma, s.index) * std::abs(s.scale),
                                    s.decimals),
                     s.unit);
  }
  return t;
}

}  // namespace

std::string ValueWithSigma(double value, double sigma, int decimals) {
  if (!std::isfinite(value)) return "–";
  if (!std::isfinite(sigma) || sigma <= 0.0) return fmt::format("{:.{}f}", value, decimals);
  return fmt::format("{:.{}f} ± {:.{}f}", value, decimals, sigma, decimals);
}

std::string ParameterTableMarkdown(const EffectResult& r) {
  if (r.theta.size() == 0) return "";
  const Layout layout = LayoutOf(r.effect);
  std::string md = fmt::format("### `{}`: {} ({})\n\n", EffectName(r.effect), layout.title, r.verdict);
  if (r.effect == Effect::kPeriodicLeadError) md += PeriodicTable(r);
  if (!layout.legs.empty()) md += LegTable(r, layout.legs);
  if (!layout.legs.empty() && !layout.scalars.empty()) md += "\n";
  if (!layout.scalars.empty()) md += ScalarTable(r, layout.scalars);
  return md;
}

}  // namespace edsp::gap
