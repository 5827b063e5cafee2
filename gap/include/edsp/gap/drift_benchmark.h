#pragma once
// edsp-gap benchmark --mode drift: edsp-gap drift scored on random whole
// rigs (rig_scenarios.h's DrawWholeRig). Each rig is calibrated on the six
// motions, then measured in two later sessions with the calibration in
// force: one where nothing changed (a new tracker set-up) and one where
// the rig did, as rigs do: a screw's backlash grown, a leg's offset jumped
// (a joint re-seated), or a warmer hall (every screw longer). Scored: a
// true change of at least 3σ (the σ drift reports) named and its size
// within 3σ; "no change" where nothing changed.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "edsp/diagnosis/effects.h"

namespace edsp::gap {

struct DriftBenchmarkOptions {
  int rigs = 10;
  std::uint64_t seed = 1;
  std::string config_path;  // nominal model; default: the paper's platform
  double tracker_noise_m = 5e-6;
  std::vector<std::string> fit_motions = {"Lz", "Lx", "Rz", "Ry", "M1", "M2"};
  std::vector<std::string> session_motions = {"Lz", "Lx", "Ry", "M3"};
  bool progress = true;
};

struct TrueChange {
  Effect effect = Effect::kLegOffset;  // backlash, or leg_offset for a leg's own length
  int leg = 0;                         // 1–6
  double change = 0.0;                 // SI
  // What drift said of it.
  double reported = 0.0, sigma = 0.0;
  bool eligible = false;  // |change| ≥ 3σ
  bool named = false, sized = false;
};

struct DriftScenario {
  int index = 0;
  std::string description, kind;  // kind: backlash | offset | two_at_once | warmer_hall
  std::vector<TrueChange> truth;
  int false_changes = 0;                       // parameters named in the changed session that did not change
  bool unchanged_quiet = false;                // the unchanged session named no change
  int unchanged_named = 0;                     //   or how many it named
  std::vector<std::string> unchanged_changes;  // each as drift's text names it
  bool recalibrate_unchanged = false, recalibrate_changed = false;
  std::string error;
};

struct DriftBenchmarkResult {
  DriftBenchmarkOptions options;
  std::vector<DriftScenario> scenarios;
  int eligible = 0, named_and_sized = 0;  // true changes of ≥ 3σ
  int unchanged = 0, unchanged_quiet = 0;
  int false_changes = 0;
};

DriftBenchmarkResult RunDriftBenchmark(const DriftBenchmarkOptions& options);
nlohmann::json ToJson(const DriftBenchmarkResult& result);
void PrintDriftBenchmark(const DriftBenchmarkResult& result);

}  // namespace edsp::gap
