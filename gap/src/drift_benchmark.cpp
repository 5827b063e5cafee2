#include "edsp/gap/drift_benchmark.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/drift.h"
#include "edsp/diagnosis/report.h"
#include "edsp/gap/rig_scenarios.h"
#include "edsp/kinematics/config.h"
#include "edsp/sim/offline_run.h"
#include "draws.h"
#include "edsp/node/build_paths.h"

namespace edsp::gap {

namespace {

OfflineRunOptions SessionRun(const DriftBenchmarkOptions& o, Rng& rng, std::uint64_t seed) {
  OfflineRunOptions run;
  run.paper.stops = 4;
  run.paper.dwell_s = 0.3;
  run.paper.max_speed_m_s = 0.25;
  run.paper.max_speed_rad_s = 0.5;
  run.tracker.noise_sigma_m = o.tracker_noise_m;
  run.tracker.rate_hz = 100.0;
  run.tracker.seed = seed;
  run.tracker.X_TB = DrawTrackerStand(rng);  // set up anew for every session
  return run;
}

// Leg `leg` (0–5) jumped by min_m–max_m either way.
void JumpLeg(int leg, double min_m, double max_m, Rng& rng, RigEffects* fx, DriftScenario* s) {
  const double jump = Uniform(rng, min_m, max_m) * (Uniform(rng, 0, 1) < 0.5 ? -1 : 1);
  fx->leg_offset.offset_m[static_cast<std::size_t>(leg)] += jump;
  s->truth.push_back({Effect::kLegOffset, leg + 1, jump});
  s->description += fmt::format("leg {} re-seated: {:+.1f} µm", leg + 1, jump * 1e6);
}

// What changed between the calibration and the second session.
RigEffects Changed(const RigEffects& before, int index, Rng& rng, DriftScenario* s) {
  RigEffects after = before;
  const int leg = static_cast<int>(Uniform(rng, 0, 6));
  const auto l = static_cast<std::size_t>(leg);
  switch (index % 4) {
    case 0: {
      s->kind = "backlash";
      const double grown = Uniform(rng, 10e-6, 30e-6);
      after.backlash.backlash_m[l] += grown;
      s->truth.push_back({Effect::kBacklash, leg + 1, grown});
      s->description = fmt::format("backlash leg {} grown by {:.1f} µm", leg + 1, grown * 1e6);
      break;
    }
    case 1:
      s->kind = "offset";
      JumpLeg(leg, 50e-6, 150e-6, rng, &after, s);
      break;
    case 2: {
      // A screw worn to 2.5× its play (at least 10 µm more) and another leg
      // re-seated, in one session.
      s->kind = "two_at_once";
      const double grown = std::max(1.5 * before.backlash.backlash_m[l], 10e-6);
      after.backlash.backlash_m[l] += grown;
      s->truth.push_back({Effect::kBacklash, leg + 1, grown});
      s->description = fmt::format("backlash leg {} +{:.1f} µm, ", leg + 1, grown * 1e6);
      JumpLeg((leg + 1 + static_cast<int>(Uniform(rng, 0, 5))) % 6, 30e-6, 60e-6, rng, &after, s);
      break;
    }
    default: {
      // Every screw longer by α·ΔT over the length that warms.
      s->kind = "warmer_hall";
      const double kelvin = Uniform(rng, 2.0, 5.0);
      const double grown = 11.7e-6 * kelvin * 0.6;
      for (std::size_t i = 0; i < 6; ++i) {
        after.leg_offset.offset_m[i] += grown;
        s->truth.push_back({Effect::kLegOffset, static_cast<int>(i) + 1, grown});
      }
      s->description = fmt::format("hall {:.1f} K warmer: every screw {:.1f} µm longer", kelvin, grown * 1e6);
    }
  }
  return after;
}

const ParameterChange* Reported(Effect effect, int leg, const std::vector<ParameterChange>& among) {
  for (const ParameterChange& c : among) {
    if (c.effect == effect && c.leg == leg) return &c;
  }
  return nullptr;
}

const LegChange* ReportedLeg(int leg, const std::vector<LegChange>& among) {
  for (const LegChange& c : among) {
    if (c.leg == leg) return &c;
  }
  return nullptr;
}

// A leg's jump is scored as the leg's length change, however the baseline
// holds the leg's geometry; a geometric parameter of that leg that changed
// with it is the same change, not a false one.
void Score(const DriftReport& changed, DriftScenario* s) {
  for (TrueChange& t : s->truth) {
    double reported = 0.0, sigma = 0.0;
    if (t.effect == Effect::kLegOffset) {
      const LegChange* leg = ReportedLeg(t.leg, changed.legs);
      if (leg == nullptr) continue;
      reported = leg->change_m, sigma = leg->sigma_m;
      t.named = ReportedLeg(t.leg, changed.legs_changed) != nullptr;
    } else {
      const ParameterChange* p = Reported(t.effect, t.leg, changed.parameters);
      if (p == nullptr) continue;  // the calibration does not apply that effect
      reported = p->change, sigma = p->sigma;
      t.named = Reported(t.effect, t.leg, changed.changed) != nullptr;
    }
    t.reported = reported;
    t.sigma = sigma;
    t.eligible = std::abs(t.change) >= 3.0 * sigma;
    t.sized = std::abs(reported - t.change) <= 3.0 * sigma;
  }
  const auto truly = [&](Effect effect, int leg) {
    return std::any_of(s->truth.begin(), s->truth.end(),
                       [&](const TrueChange& t) { return t.effect == effect && t.leg == leg; });
  };
  for (const ParameterChange& c : changed.changed) {
    s->false_changes += !truly(c.effect, c.leg) && !(IsLegGeometry(c.effect) && truly(Effect::kLegOffset, c.leg));
  }
  for (const LegChange& c : changed.legs_changed) s->false_changes += !truly(Effect::kLegOffset, c.leg);
}

}  // namespace

DriftBenchmarkResult RunDriftBenchmark(const DriftBenchmarkOptions& o) {
  DriftBenchmarkResult result;
  result.options = o;
  const std::string config = o.config_path.empty() ? SourcePath("config/huang2021.toml") : o.config_path;
  const PlatformModel model(LoadConfigFile(config));
  const double rating = WholeRigRatedPayload(model);
  const std::string root =
      (std::filesystem::temp_directory_path() / fmt::format("edsp-gap-drift-bench-{}", ::getpid())).string();
  Rng rng(o.seed);
  for (int k = 0; k < o.rigs; ++k) {
    if (o.progress) std::fprintf(stderr, "\rrig %d/%d", k, o.rigs), std::fflush(stderr);
    const Scenario rig = DrawWholeRig(o.seed + 7, k, rating);
    DriftScenario s;
    s.index = k;
    const RigEffects after = Changed(rig.effects, k, rng, &s);
    const std::string dir = fmt::format("{}/rig-{:03d}", root, k);
    try {
      OfflineRunOptions fit = SessionRun(o, rng, o.seed * 7919 + static_cast<std::uint64_t>(3 * k));
      fit.motions = o.fit_motions;
      fit.out_dir = dir + "/fit";
      const Diagnosis d = Diagnose(model, LoadMeasurement(RunOffline(config, rig.effects, fit).csv_path));
      const nlohmann::json baseline = ModelJson(d);
      const std::string model_path = dir + "/model.json";
      std::ofstream(model_path) << baseline.dump();
      const auto session = [&](const RigEffects& fx, const char* name, std::uint64_t seed) {
        OfflineRunOptions run = SessionRun(o, rng, seed);
        run.motions = o.session_motions;
        run.calibration_path = model_path;
        run.out_dir = dir + "/" + name;
        return Drift(model, baseline, model_path, LoadMeasurement(RunOffline(config, fx, run).csv_path));
      };
      const DriftReport same = session(rig.effects, "same", o.seed * 7919 + static_cast<std::uint64_t>(3 * k + 1));
      const DriftReport changed = session(after, "changed", o.seed * 7919 + static_cast<std::uint64_t>(3 * k + 2));
      s.unchanged_named = static_cast<int>(same.changed.size() + same.legs_changed.size());
      s.unchanged_quiet = s.unchanged_named == 0;
      for (const LegChange& c : same.legs_changed) s.unchanged_changes.push_back(LegChangeText(c));
      for (const ParameterChange& c : same.changed) s.unchanged_changes.push_back(ChangeText(c));
      s.recalibrate_unchanged = same.recalibrate;
      s.recalibrate_changed = changed.recalibrate;
      Score(changed, &s);
    } catch (const std::exception& e) {
      s.error = e.what();
    }
    std::filesystem::remove_all(dir);
    result.unchanged += s.error.empty();
    result.unchanged_quiet += s.unchanged_quiet;
    result.false_changes += s.false_changes;
    for (const TrueChange& t : s.truth) {
      result.eligible += t.eligible;
      result.named_and_sized += t.eligible && t.named && t.sized;
    }
    result.scenarios.push_back(s);
  }
  if (o.progress) std::fprintf(stderr, "\rrig %d/%d\n", o.rigs, o.rigs);
  std::filesystem::remove_all(root);
  return result;
}

nlohmann::json ToJson(const DriftBenchmarkResult& r) {
  nlohmann::json j;
  j["mode"] = "drift";
  j["seed"] = r.options.seed;
  j["tracker_noise_m"] = r.options.tracker_noise_m;
  j["fit_motions"] = r.options.fit_motions;
  j["session_motions"] = r.options.session_motions;
  j["changes_of_3_sigma"] = r.eligible;
  j["named_and_sized"] = r.named_and_sized;
  j["named_and_sized_rate"] = r.eligible ? static_cast<double>(r.named_and_sized) / r.eligible : 0.0;
  j["unchanged_sessions"] = r.unchanged;
  j["unchanged_quiet"] = r.unchanged_quiet;
  j["unchanged_quiet_rate"] = r.unchanged ? static_cast<double>(r.unchanged_quiet) / r.unchanged : 0.0;
  j["false_changes"] = r.false_changes;
  j["targets"] = {{"named_and_sized_rate", 0.90}, {"unchanged_quiet_rate", 0.95}};
  j["scenarios"] = nlohmann::json::array();
  for (const DriftScenario& s : r.scenarios) {
    nlohmann::json truth = nlohmann::json::array();
    for (const TrueChange& t : s.truth) {
      truth.push_back({{"effect", EffectName(t.effect)},
                       {"leg", t.leg},
                       {"change", t.change},
                       {"reported", t.reported},
                       {"sigma", t.sigma},
                       {"eligible", t.eligible},
                       {"named", t.named},
                       {"sized", t.sized}});
    }
    nlohmann::json js = {{"index", s.index},
                         {"kind", s.kind},
                         {"description", s.description},
                         {"truth", truth},
                         {"false_changes", s.false_changes},
                         {"unchanged_quiet", s.unchanged_quiet},
                         {"unchanged_named", s.unchanged_named},
                         {"unchanged_changes", s.unchanged_changes},
                         {"recalibrate_unchanged", s.recalibrate_unchanged},
                         {"recalibrate_changed", s.recalibrate_changed}};
    if (!s.error.empty()) js["error"] = s.error;
    j["scenarios"].push_back(js);
  }
  return j;
}

void PrintDriftBenchmark(const DriftBenchmarkResult& r) {
  for (const DriftScenario& s : r.scenarios) {
    int eligible = 0, found = 0;
    for (const TrueChange& t : s.truth) eligible += t.eligible, found += t.eligible && t.named && t.sized;
    std::printf("%-3d %-50.50s named and sized %d of %d (≥ 3σ), false %d; unchanged session: %s%s\n", s.index,
                s.description.c_str(), found, eligible, s.false_changes,
                s.unchanged_quiet ? "no change" : fmt::format("{} named", s.unchanged_named).c_str(),
                s.error.empty() ? "" : (" ERROR " + s.error).c_str());
  }
  std::printf(
      "changes of ≥ 3σ named and sized: %d of %d (target 90%%); unchanged sessions quiet: %d of %d "
      "(target 95%%); false changes: %d\n",
      r.named_and_sized, r.eligible, r.unchanged_quiet, r.unchanged, r.false_changes);
}

}  // namespace edsp::gap
