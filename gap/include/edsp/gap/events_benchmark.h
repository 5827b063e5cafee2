#pragma once
// edsp-gap benchmark --mode events: the search for changes within a session
// (diagnosis/change_point.h) scored on the independently written rig
// (blindrig/). Scenario k is a rig the blind rig draws (none, one or two
// effects of the vocabulary; index % 5 < 4 of DrawBlindScenario, its own
// tracker rate, noise and encoders) that, by k % 4,
//   0: one leg's length steps (±20–100 µm, a random leg, at a random instant
//      in the middle 70% of the session),
//   1: the tracker's stand is knocked (30–80 µm and 20–60 µrad, random
//      directions, at a random instant),
//   2: drifts slowly (a screw warming under power: thermal, τ 300–900 s),
//   3: does not change.
// Scored: a step found (an event of its kind, a leg's on its leg: the
// closest in time), and apart whether it was timed within 1 s and sized
// within 20% (a leg's length; the tracker's rotation); a false event (any
// event of a rig without a step, or beside the step's); a step the
// diagnosis still names thermal_drift for (on a rig drawn without it); a
// drift reported as a step. A scenario that fails to run counts as an
// error and in nothing else.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace edsp::gap {

struct EventsBenchmarkOptions {
  int scenarios = 8;
  std::uint64_t seed = 1;
  std::string config_path;  // nominal model; default: the paper's platform
  std::vector<std::string> motions = {"Lz", "Lx", "Rz", "Ry", "M1", "M2"};
  std::string keep_dir;  // non-empty: each scenario's data.csv and diagnosis.json in <keep_dir>/scenario-NNN
  bool progress = true;
};

// What a scenario's rig does within the session.
enum class SessionChange { kLegStep, kTrackerStep, kDrift, kNone };
const char* SessionChangeName(SessionChange change);  // the JSON's `kind`: leg_step, tracker_step, drift, none
bool IsStep(SessionChange change);

struct EventScenario {
  int index = 0;
  SessionChange kind = SessionChange::kNone;
  std::string rig;          // the blind rig's draw, as it describes it
  std::string description;  // the change, as drawn
  double time_s = -1.0;     // the change's instant (steps)
  int leg = -1;             // 0-based (leg_step)
  double size = 0.0;        // leg: m; tracker: its rotation, rad
  // What the diagnosis said.
  std::vector<std::string> events;  // DescribeEvent of each
  bool detected = false, timed = false, sized = false;
  double time_error_s = 0.0, size_error = 0.0;  // of the matching event; size: relative
  int false_events = 0;
  bool step_named_thermal = false;  // a step with thermal_drift still selected
  bool drift_as_step = false;       // a drift with an event
  double diagnose_s = 0.0;
  std::string error;
};

struct EventsBenchmarkResult {
  EventsBenchmarkOptions options;
  std::vector<EventScenario> scenarios;
  int steps = 0, detected = 0, timed = 0, sized = 0;
  int unchanged = 0, unchanged_with_event = 0;  // rigs without a step (drifts included)
  int false_events = 0, steps_named_thermal = 0, drifts_as_steps = 0;
  double median_diagnose_s = 0.0;
  int errors = 0;  // scenarios that failed to run
};

EventsBenchmarkResult RunEventsBenchmark(const EventsBenchmarkOptions& options);
nlohmann::json ToJson(const EventsBenchmarkResult& result);
void PrintEventsBenchmark(const EventsBenchmarkResult& result);

}  // namespace edsp::gap
