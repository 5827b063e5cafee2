#include "edsp/gap/events_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "draws.h"
#include "edsp/blindrig/blind_kinematics.h"
#include "edsp/blindrig/blind_setup.h"
#include "edsp/diagnosis/diagnose.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/build_paths.h"

namespace edsp::gap {

namespace {

constexpr double kTimeToleranceS = 1.0;
constexpr double kSizeTolerance = 0.2;

// The session's length as the blind rig runs it (a second between motions).
double SessionSeconds(const blind::BlindRigSetup& setup) {
  double total = 0.0;
  for (const std::string& name : setup.motions) total += blind::MotionNamed(setup, name).duration_s() + 1.0;
  return total;
}

Eigen::Vector3d RandomDirection(Rng& rng) {
  std::normal_distribution<double> normal;
  Eigen::Vector3d v(normal(rng), normal(rng), normal(rng));
  return v.normalized();
}

// The change of scenario k, drawn into the rig's effects.
void DrawChange(int k, double session_s, const blind::Vec6& tracker_frame, Rng& rng, blind::BlindEffects* effects,
                EventScenario* s) {
  const double instant = Uniform(rng, 0.15, 0.85) * session_s;
  switch (k % 4) {
    case 0: {
      s->kind = SessionChange::kLegStep;
      s->leg = static_cast<int>(Uniform(rng, 0, 6));
      s->size = Uniform(rng, 20e-6, 100e-6) * (Uniform(rng, 0, 1) < 0.5 ? -1 : 1);
      s->time_s = instant;
      effects->change_time_s = instant;
      effects->change_leg = s->leg;
      effects->change_m = s->size;
      s->description = fmt::format("leg {} {:+.1f} µm at {:.2f} s", s->leg + 1, s->size * 1e6, instant);
      break;
    }
    case 1: {
      s->kind = SessionChange::kTrackerStep;
      const Eigen::Vector3d moved = Uniform(rng, 30e-6, 80e-6) * RandomDirection(rng);
      const Eigen::Vector3d turned = Uniform(rng, 20e-6, 60e-6) * RandomDirection(rng);
      s->time_s = instant;
      effects->change_time_s = instant;
      effects->change_tracker << moved, turned;
      // The angle the stand turned by (the drawn roll, pitch and yaw steps
      // are not a rotation vector where the stand is tilted).
      const Eigen::Matrix3d turn =
          blind::Rotation(tracker_frame + effects->change_tracker) * blind::Rotation(tracker_frame).transpose();
      s->size = Eigen::AngleAxisd(turn).angle();
      s->description =
          fmt::format("tracker knocked {:.1f} µm, {:.1f} µrad at {:.2f} s", moved.norm() * 1e6, s->size * 1e6, instant);
      break;
    }
    case 2: {
      s->kind = SessionChange::kDrift;
      effects->heating_K_per_m = 0.0;  // a thermal effect the rig drew is replaced by this one
      effects->alpha_per_K = 11.5e-6;
      effects->heating_K_per_s = Uniform(rng, 0.01, 0.03);
      effects->thermal_tau_s = Uniform(rng, 300.0, 900.0);
      s->description =
          fmt::format("screws warming {:.3f} K/s, τ {:.0f} s", effects->heating_K_per_s, effects->thermal_tau_s);
      break;
    }
    default: s->kind = SessionChange::kNone; s->description = "no change";
  }
}

bool Matches(const EventScenario& s, const ChangeEvent& e) {
  if (s.kind == SessionChange::kLegStep) return e.kind == ChangeKind::kLegLength && e.leg == s.leg;
  return s.kind == SessionChange::kTrackerStep && e.kind == ChangeKind::kTrackerFrame;
}

// The event's size beside the truth's, relative: a leg's step; the
// tracker's rotation (its translation depends on the point the frame turns
// about, which the two rigs need not share).
double SizeError(const EventScenario& s, const ChangeEvent& e) {
  const double found = s.kind == SessionChange::kLegStep ? e.size(0) : e.size.tail<3>().norm();
  return (found - s.size) / std::abs(s.size);
}

void Score(const Diagnosis& d, bool rig_has_thermal, EventScenario* s) {
  const bool step = IsStep(s->kind);
  // The step's event: of its kind, the closest in time; every other is false.
  const ChangeEvent* match = nullptr;
  for (const ChangeEvent& e : d.changes.events) {
    s->events.push_back(DescribeEvent(e));
    if (step && Matches(*s, e) &&
        (match == nullptr || std::abs(e.time_s - s->time_s) < std::abs(match->time_s - s->time_s)))
      match = &e;
  }
  s->false_events = static_cast<int>(d.changes.events.size()) - (match != nullptr ? 1 : 0);
  if (match != nullptr) {
    s->detected = true;
    s->time_error_s = match->time_s - s->time_s;
    s->size_error = SizeError(*s, *match);
    s->timed = std::abs(s->time_error_s) <= kTimeToleranceS;
    s->sized = std::abs(s->size_error) <= kSizeTolerance;
  }
  const bool thermal = std::find(d.selected.begin(), d.selected.end(), Effect::kThermalDrift) != d.selected.end();
  s->step_named_thermal = step && thermal && !rig_has_thermal;
  s->drift_as_step = s->kind == SessionChange::kDrift && !d.changes.events.empty();
}

void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error(path + ": cannot write");
}

// A scenario's data and its diagnosis, to look at again (edsp-gap diagnose
// --data DIR/data.csv); a directory that cannot be written stops the run.
void Keep(const std::string& dir, const std::string& csv, const Diagnosis& d) {
  std::filesystem::create_directories(dir);
  WriteFile(dir + "/data.csv", csv);
  WriteFile(dir + "/diagnosis.json", ToJson(d).dump(2) + "\n");
}

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

const char* SessionChangeName(SessionChange change) {
  switch (change) {
    case SessionChange::kLegStep: return "leg_step";
    case SessionChange::kTrackerStep: return "tracker_step";
    case SessionChange::kDrift: return "drift";
    case SessionChange::kNone: return "none";
  }
  return "none";
}

bool IsStep(SessionChange change) { return change == SessionChange::kLegStep || change == SessionChange::kTrackerStep; }

EventsBenchmarkResult RunEventsBenchmark(const EventsBenchmarkOptions& o) {
  EventsBenchmarkResult result;
  result.options = o;
  const PlatformConfig config =
      LoadConfigFile(o.config_path.empty() ? SourcePath("config/huang2021.toml") : o.config_path);
  const PlatformModel model(config);
  blind::BlindRigSetup setup = blind::SetupFromConfig(config);
  setup.motions = o.motions;
  const double session_s = SessionSeconds(setup);
  if (!o.keep_dir.empty()) std::filesystem::create_directories(o.keep_dir);  // a place it cannot write: before any work
  Rng rng(o.seed * 104729 + 17);
  std::vector<double> seconds;
  for (int k = 0; k < o.scenarios; ++k) {
    if (o.progress) std::fprintf(stderr, "\rscenario %d/%d", k, o.scenarios), std::fflush(stderr);
    // The blind rig's draws of none, one or two effects (its fifth, outside
    // the vocabulary, left out: the effects benchmark scores those), turned
    // a slot each four scenarios, so that every change meets every kind.
    blind::BlindScenario rig = blind::DrawBlindScenario(o.seed, 5 * (k / 4) + (k + k / 4) % 4);
    EventScenario s;
    s.index = k;
    s.rig = rig.description;
    const bool rig_has_thermal = std::find(rig.truth.begin(), rig.truth.end(), "thermal_drift") != rig.truth.end();
    DrawChange(k, session_s, rig.tracker.frame, rng, &rig.effects, &s);
    if (s.kind == SessionChange::kDrift && rig_has_thermal) s.rig += " (its thermal effect replaced by the drift)";
    std::string csv;
    std::optional<Diagnosis> d;
    try {
      csv = blind::GenerateMeasurementCsv(setup, rig.effects, rig.tracker);
      const MeasurementData data = ParseMeasurementCsv(csv, "blind");
      const auto t0 = std::chrono::steady_clock::now();
      d = Diagnose(model, data);
      s.diagnose_s = SecondsSince(t0);
      seconds.push_back(s.diagnose_s);
      Score(*d, rig_has_thermal, &s);
    } catch (const std::exception& e) {
      s.error = e.what();
    }
    if (!o.keep_dir.empty() && d) Keep(fmt::format("{}/scenario-{:03d}", o.keep_dir, k), csv, *d);
    const bool step = IsStep(s.kind);
    result.scenarios.push_back(s);
    if (!s.error.empty()) {  // scored on none of the counts below
      result.errors += 1;
      continue;
    }
    result.steps += step;
    result.detected += s.detected;
    result.timed += s.detected && s.timed;
    result.sized += s.detected && s.sized;
    result.unchanged += !step;
    result.unchanged_with_event += !step && !s.events.empty();
    result.false_events += s.false_events;
    result.steps_named_thermal += s.step_named_thermal;
    result.drifts_as_steps += s.drift_as_step;
  }
  if (o.progress) std::fprintf(stderr, "\rscenario %d/%d\n", o.scenarios, o.scenarios);
  result.median_diagnose_s = Median(seconds);
  return result;
}

nlohmann::json ToJson(const EventsBenchmarkResult& r) {
  const auto rate = [](int n, int of) { return of ? static_cast<double>(n) / of : 0.0; };
  nlohmann::json j;
  j["mode"] = "events";
  j["seed"] = r.options.seed;
  j["motions"] = r.options.motions;
  j["steps"] = r.steps;
  j["detected"] = r.detected;
  j["detected_rate"] = rate(r.detected, r.steps);
  j["timed_within_1s"] = r.timed;
  j["sized_within_20pct"] = r.sized;
  j["unchanged"] = r.unchanged;
  j["unchanged_with_event"] = r.unchanged_with_event;
  j["false_event_rate"] = rate(r.unchanged_with_event, r.unchanged);
  j["false_events"] = r.false_events;
  j["steps_named_thermal_drift"] = r.steps_named_thermal;
  j["drifts_as_steps"] = r.drifts_as_steps;
  j["median_diagnose_s"] = r.median_diagnose_s;
  j["errors"] = r.errors;
  j["targets"] = {{"detected_rate", 0.95}, {"false_event_rate", 0.05}};
  j["scenarios"] = nlohmann::json::array();
  for (const EventScenario& s : r.scenarios) {
    nlohmann::json js = {{"index", s.index},
                         {"kind", SessionChangeName(s.kind)},
                         {"rig", s.rig},
                         {"change", s.description},
                         {"events", s.events},
                         {"detected", s.detected},
                         {"timed", s.timed},
                         {"sized", s.sized},
                         {"false_events", s.false_events},
                         {"step_named_thermal_drift", s.step_named_thermal},
                         {"drift_as_step", s.drift_as_step},
                         {"diagnose_s", s.diagnose_s}};
    if (s.detected) {
      js["time_error_s"] = s.time_error_s;
      js["size_error"] = s.size_error;
    }
    if (!s.error.empty()) js["error"] = s.error;
    j["scenarios"].push_back(js);
  }
  return j;
}

void PrintEventsBenchmark(const EventsBenchmarkResult& r) {
  for (const EventScenario& s : r.scenarios) {
    std::string found = s.events.empty() ? "no event" : fmt::format("{} event(s)", s.events.size());
    if (s.detected) found += fmt::format(": found, {:+.2f} s, size {:+.0f}%", s.time_error_s, s.size_error * 100.0);
    std::printf("%-3d %-12s %-44.44s %s%s%s%s\n", s.index, SessionChangeName(s.kind), s.description.c_str(),
                found.c_str(), s.false_events ? fmt::format(", {} false", s.false_events).c_str() : "",
                s.step_named_thermal ? ", thermal_drift named" : "",
                s.error.empty() ? "" : (" ERROR " + s.error).c_str());
  }
  std::printf(
      "steps found: %d of %d (target 95%%), timed within 1 s: %d, sized within 20%%: %d; rigs without a step "
      "with an event: %d of %d (target ≤ 5%%); steps still named thermal_drift: %d; drifts taken for steps: %d; "
      "median diagnosis %.1f s; scenarios that failed to run: %d\n",
      r.detected, r.steps, r.timed, r.sized, r.unchanged_with_event, r.unchanged, r.steps_named_thermal,
      r.drifts_as_steps, r.median_diagnose_s, r.errors);
}

}  // namespace edsp::gap
