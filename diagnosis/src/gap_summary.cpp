#include "edsp/diagnosis/gap_summary.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace edsp::gap {

namespace {

constexpr double kRestSpeed = 1e-5;     // m/s of every leg
constexpr double kAccelerating = 0.05;  // m/s² of some leg

struct Accumulator {
  double sum2 = 0.0, max = 0.0;
  int n = 0;
  void Add(double norm) {
    sum2 += norm * norm;
    max = std::max(max, norm);
    ++n;
  }
  RmsMax Get() const { return {n ? std::sqrt(sum2 / n) : 0.0, max, n}; }
};

double Norm3(const Eigen::VectorXd& r, int sample) { return r.segment<3>(3 * sample).norm(); }

std::string Phase(const Design& d, int k) {
  const std::size_t s = static_cast<std::size_t>(k);
  if (d.leg_velocity_m_s[s].cwiseAbs().maxCoeff() < kRestSpeed) return "at_rest";
  if (d.leg_accel_m_s2[s].cwiseAbs().maxCoeff() > kAccelerating) return "accelerating";
  return "cruising";
}

std::string Where(const GapSummary& g) {
  std::string text;
  if (!g.by_run.empty()) {
    const auto worst = std::max_element(g.by_run.begin(), g.by_run.end(),
                                        [](const auto& a, const auto& b) { return a.second.rms_m < b.second.rms_m; });
    text += fmt::format("Largest in run {} (RMS {:.1f} µm, max {:.1f} µm). ", worst->first, worst->second.rms_m * 1e6,
                        worst->second.max_m * 1e6);
  }
  const auto leg = std::max_element(g.by_leg_m.begin(), g.by_leg_m.end());
  text +=
      fmt::format("In leg space leg {} carries the most ({:.1f} µm RMS). ", leg - g.by_leg_m.begin() + 1, *leg * 1e6);
  double flip = 0.0;
  int flip_leg = 0;
  for (int i = 0; i < 6; ++i) {
    const double f =
        std::abs(g.extending_mean_m[static_cast<std::size_t>(i)] - g.retracting_mean_m[static_cast<std::size_t>(i)]);
    if (f > flip) flip = f, flip_leg = i;
  }
  text += fmt::format("Extending vs retracting differs by up to {:.1f} µm (leg {}). ", flip * 1e6, flip_leg + 1);
  std::vector<std::string> phases;
  for (const auto& [phase, s] : g.by_phase) phases.push_back(fmt::format("{} {:.1f} µm", phase, s.rms_m * 1e6));
  text += "By phase (RMS): " + fmt::format("{}", fmt::join(phases, ", ")) + ". ";
  std::vector<std::string> regions;
  for (const char* r : {"near", "mid", "far"}) {
    const auto it = g.by_region.find(r);
    if (it != g.by_region.end()) regions.push_back(fmt::format("{} {:.1f} µm", r, it->second.rms_m * 1e6));
  }
  text += "By distance from home: " + fmt::format("{}", fmt::join(regions, ", ")) + ".";
  if (g.over_time.size() >= 2) {
    text += fmt::format(" Over time: first tenth {:.1f} µm, last tenth {:.1f} µm.",
                        g.over_time.front().second.rms_m * 1e6, g.over_time.back().second.rms_m * 1e6);
  }
  if (g.has_encoder) {
    const double servo = *std::max_element(g.servo_tracking_m.begin(), g.servo_tracking_m.end());
    text += fmt::format(
        " Servo tracking (command − encoder) up to {:.1f} µm RMS per leg; with the encoders' "
        "legs the mechanism's gap is {:.1f} µm RMS.",
        servo * 1e6, g.mechanism.rms_m * 1e6);
  }
  return text;
}

}  // namespace

RmsMax PointStats(const Eigen::VectorXd& r, int begin, int count) {
  Accumulator a;
  for (int k = begin; k < begin + count; ++k) a.Add(Norm3(r, k));
  return a.Get();
}

GapSummary SummarizeGap(const Design& d, const Eigen::VectorXd& r) {
  GapSummary g;
  const int n = d.samples();
  g.overall = PointStats(r, 0, n);
  for (std::size_t run = 0; run < d.run_samples.size(); ++run) {
    g.by_run.emplace_back(d.runs[run], PointStats(r, d.run_samples[run].begin, d.run_samples[run].count));
  }
  // Leg space: the smallest leg errors that move A by the residual.
  Vector6 sum2 = Vector6::Zero(), ext_sum = Vector6::Zero(), ret_sum = Vector6::Zero();
  Vector6 ext_n = Vector6::Zero(), ret_n = Vector6::Zero(), servo2 = Vector6::Zero();
  std::map<std::string, Accumulator> phases, regions;
  std::vector<double> sorted = d.displacement;
  std::sort(sorted.begin(), sorted.end());
  const double third = sorted.empty() ? 0.0 : sorted[sorted.size() / 3];
  const double two_thirds = sorted.empty() ? 0.0 : sorted[2 * sorted.size() / 3];
  Accumulator mechanism;
  for (int k = 0; k < n; ++k) {
    const std::size_t s = static_cast<std::size_t>(k);
    const Vector3 rk = r.segment<3>(3 * k);
    const Vector6 dl = d.point_per_leg[s].jacobiSvd(Eigen::ComputeFullU | Eigen::ComputeFullV).solve(rk);
    sum2 += dl.cwiseAbs2();
    for (int i = 0; i < 6; ++i) {
      const double v = d.leg_velocity_m_s[s](i);
      if (v > kRestSpeed) ext_sum(i) += dl(i), ext_n(i) += 1;
      if (v < -kRestSpeed) ret_sum(i) += dl(i), ret_n(i) += 1;
    }
    phases[Phase(d, k)].Add(rk.norm());
    const double x = d.displacement[s];
    regions[x <= third ? "near" : (x <= two_thirds ? "mid" : "far")].Add(rk.norm());
    if (d.has_encoder) {
      servo2 += d.servo_error_m[s].cwiseAbs2();
      // The legs really stood at the encoders' lengths: A moved by G·(enc − cmd).
      mechanism.Add((rk + d.point_per_leg[s] * d.servo_error_m[s]).norm());
    }
  }
  for (int i = 0; i < 6; ++i) {
    const std::size_t s = static_cast<std::size_t>(i);
    g.by_leg_m[s] = n ? std::sqrt(sum2(i) / n) : 0.0;
    g.extending_mean_m[s] = ext_n(i) > 0 ? ext_sum(i) / ext_n(i) : 0.0;
    g.retracting_mean_m[s] = ret_n(i) > 0 ? ret_sum(i) / ret_n(i) : 0.0;
    g.servo_tracking_m[s] = n ? std::sqrt(servo2(i) / n) : 0.0;
  }
  for (const auto& [name, a] : phases) g.by_phase[name] = a.Get();
  for (const auto& [name, a] : regions) g.by_region[name] = a.Get();
  constexpr int kParts = 10;
  for (int part = 0; part < kParts && n >= kParts; ++part) {
    const int begin = n * part / kParts, end = n * (part + 1) / kParts;
    // Samples are grouped by run; time order within the data is run order.
    g.over_time.emplace_back(d.time_s[static_cast<std::size_t>(begin)], PointStats(r, begin, end - begin));
  }
  g.has_encoder = d.has_encoder;
  g.mechanism = mechanism.Get();
  g.where = Where(g);
  return g;
}

nlohmann::json ToJson(const GapSummary& g) {
  auto stats = [](const RmsMax& s) {
    return nlohmann::json{{"rms_m", s.rms_m}, {"max_m", s.max_m}, {"samples", s.samples}};
  };
  nlohmann::json j;
  j["rms_m"] = g.overall.rms_m;
  j["max_m"] = g.overall.max_m;
  j["by_run"] = nlohmann::json::object();
  for (const auto& [run, s] : g.by_run) j["by_run"][run] = stats(s);
  j["by_leg_m"] = g.by_leg_m;
  j["by_direction_m"] = {{"extending_mean", g.extending_mean_m}, {"retracting_mean", g.retracting_mean_m}};
  j["by_phase"] = nlohmann::json::object();
  for (const auto& [phase, s] : g.by_phase) j["by_phase"][phase] = stats(s);
  j["by_region"] = nlohmann::json::object();
  for (const auto& [region, s] : g.by_region) j["by_region"][region] = stats(s);
  j["over_time"] = nlohmann::json::array();
  for (const auto& [t, s] : g.over_time) {
    nlohmann::json o = stats(s);
    o["from_time_s"] = t;
    j["over_time"].push_back(o);
  }
  if (g.has_encoder) {
    j["servo_tracking_m"] = g.servo_tracking_m;
    j["mechanism"] = stats(g.mechanism);
  }
  j["where"] = g.where;
  return j;
}

}  // namespace edsp::gap
