#include "edsp/diagnosis/calibration_check.h"

#include <fstream>

#include <fmt/format.h>

#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/diagnosis/gnuplot.h"
#include "edsp/diagnosis/measurement_data.h"

namespace edsp::gap {

namespace {

constexpr double kFloorFactor = 1.5;    // after ≤ 1.5 × the tracker's noise floor, or
constexpr double kTargetShrink = 0.90;  // 90% lower than without the calibration

const RunEvaluation* Find(const Evaluation& e, const std::string& run) {
  for (const RunEvaluation& r : e.by_run) {
    if (r.run == run) return &r;
  }
  return nullptr;
}

nlohmann::json Stats(const RmsMax& s) { return {{"rms_m", s.rms_m}, {"max_m", s.max_m}}; }

nlohmann::json MotionJson(const MotionCheck& m) {
  nlohmann::json j = {{"run", m.run}, {"before", Stats(m.before)}, {"after", Stats(m.after)}, {"shrink", m.shrink}};
  if (m.predicted) j["predicted"] = Stats(*m.predicted);
  return j;
}

std::string Row(const MotionCheck& m) {
  std::string row = fmt::format("{:<10} {:>8.1f} {:>8.1f} {:>8.1f} {:>8.1f} {:>7.0f}%", m.run, m.before.rms_m * 1e6,
                                m.before.max_m * 1e6, m.after.rms_m * 1e6, m.after.max_m * 1e6, 100 * m.shrink);
  if (m.predicted) row += fmt::format(" {:>10.1f}", m.predicted->rms_m * 1e6);
  return row + "\n";
}

}  // namespace

CalibrationCheck CheckCalibration(const Evaluation& without, const Evaluation& with, bool predicted) {
  CalibrationCheck c;
  for (const RunEvaluation& b : without.by_run) {
    const RunEvaluation* a = Find(with, b.run);
    if (a == nullptr)
      throw MeasurementError("run " + b.run + " is in the measurement without the calibration, not in the one with it");
    MotionCheck m{b.run, b.before, a->before, std::nullopt, Shrink(b.before.rms_m, a->before.rms_m)};
    if (predicted) m.predicted = b.after;
    c.motions.push_back(m);
  }
  for (const RunEvaluation& a : with.by_run) {
    if (Find(without, a.run) == nullptr) {
      throw MeasurementError("run " + a.run + " is in the measurement with the calibration, not in the one without it");
    }
  }
  c.overall = {"all", without.before, with.before, std::nullopt, Shrink(without.before.rms_m, with.before.rms_m)};
  if (predicted) c.overall.predicted = without.after;
  c.noise_floor_rms_m = with.noise_floor_rms_m;
  c.timing_excluded_before = without.timing_excluded;
  c.timing_excluded_after = with.timing_excluded;
  c.timing_share_before = without.timing_excluded_share;
  c.timing_share_after = with.timing_excluded_share;
  c.timing_kept_before = without.timing_kept;
  c.timing_kept_after = with.timing_kept;
  c.timing_kept_share_before = without.timing_kept_share;
  c.timing_kept_share_after = with.timing_kept_share;
  c.target_met = c.overall.after.rms_m <= kFloorFactor * c.noise_floor_rms_m || c.overall.shrink >= kTargetShrink;
  return c;
}

nlohmann::json ToJson(const CalibrationCheck& c) {
  nlohmann::json motions = nlohmann::json::array();
  for (const MotionCheck& m : c.motions) motions.push_back(MotionJson(m));
  nlohmann::json j = MotionJson(c.overall);
  j.erase("run");
  j["motions"] = motions;
  j["noise_floor_rms_m"] = c.noise_floor_rms_m;
  j["timing_excluded_samples"] = {{"before", c.timing_excluded_before}, {"after", c.timing_excluded_after}};
  j["timing_kept_samples"] = {{"before", c.timing_kept_before}, {"after", c.timing_kept_after}};
  j["target"] = fmt::format("RMS <= {} x noise floor or shrink >= {:.0f}%", kFloorFactor, 100 * kTargetShrink);
  j["target_met"] = c.target_met;
  return j;
}

std::string CheckTable(const CalibrationCheck& c) {
  const bool predicted = c.overall.predicted.has_value();
  std::string t = "point A after the best rigid alignment (µm)\n";
  t += fmt::format("{:<10} {:>8} {:>8} {:>8} {:>8} {:>8}{}\n", "motion", "before", "max", "after", "max", "shrink",
                   predicted ? "  predicted" : "");
  for (const MotionCheck& m : c.motions) t += Row(m);
  t += Row(c.overall);
  t += fmt::format("tracker noise floor {:.1f} µm RMS; target (≤ {:.1f} µm or ≥ {:.0f}% lower): {}\n",
                   c.noise_floor_rms_m * 1e6, kFloorFactor * c.noise_floor_rms_m * 1e6, 100 * kTargetShrink,
                   c.target_met ? "met" : "NOT met");
  if (c.timing_excluded_before + c.timing_excluded_after > 0) {
    t += fmt::format(
        "left out near stalls of the real-time system (timing_event): {} samples before ({:.1f}%), {} after "
        "({:.1f}%)\n",
        c.timing_excluded_before, 100 * c.timing_share_before, c.timing_excluded_after, 100 * c.timing_share_after);
  }
  if (c.timing_kept_before + c.timing_kept_after > 0) {
    t += fmt::format(
        "kept on request, though flagged near stalls of the real-time system (timing_event): {} samples before "
        "({:.1f}%), {} after ({:.1f}%)\n",
        c.timing_kept_before, 100 * c.timing_kept_share_before, c.timing_kept_after, 100 * c.timing_kept_share_after);
  }
  return t;
}

std::string WriteCheckPlot(const CalibrationCheck& c, const std::string& dir) {
  std::ofstream data(dir + "/calibration.dat");
  data << "# motion before_rms after_rms predicted_rms before_max after_max (µm)\n";
  for (const MotionCheck& m : c.motions) {
    data << m.run << " " << m.before.rms_m * 1e6 << " " << m.after.rms_m * 1e6 << " "
         << (m.predicted ? m.predicted->rms_m * 1e6 : 0.0) << " " << m.before.max_m * 1e6 << " " << m.after.max_m * 1e6
         << "\n";
  }
  data.close();
  const std::string predicted = c.overall.predicted ? ", '' using 4 title 'predicted RMS'" : "";
  const std::string script = fmt::format(
      "set style data histograms\nset style fill solid 0.6\nset ylabel 'point A error (µm)'\n"
      "set title 'Motions the calibration never saw: before and after (noise floor {:.1f} µm)'\n"
      "plot '{}/calibration.dat' using 2:xtic(1) title 'before RMS', '' using 3 title 'after RMS'{}, "
      "'' using 5 title 'before max', '' using 6 title 'after max'\n",
      c.noise_floor_rms_m * 1e6, dir, predicted);
  return GnuplotPng(dir, "calibration.png", script) ? dir + "/calibration.png" : "";
}

}  // namespace edsp::gap
