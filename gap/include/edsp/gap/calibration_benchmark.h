#pragma once
// edsp-gap benchmark --mode calibration: the calibration loop closed on
// random whole rigs (every static effect class at once, payloads up to the
// drives' rating: rig_scenarios.h's DrawWholeRig), once per motion design.
// Each rig runs each design's fit motions, is diagnosed blind (the CSV and
// the nominal model only), and its saved model is applied by the kinematics
// on held-out motions no fit saw, measured without and with it on the rig.
// A design meets the target on a rig when the calibrated held-out RMS is
// within 1.5× the tracker's noise floor or 90% below the uncalibrated one,
// with the worst error no larger than before.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "edsp/gap/generator.h"

namespace edsp::gap {

struct MotionDesign {
  std::string name;
  std::vector<std::string> motions;
};

struct CalibrationBenchmarkOptions {
  int rigs = 10;
  std::uint64_t seed = 1;
  // kRig: rig_scenarios.h's DrawWholeRig; kBlind: blindrig/'s
  // DrawBlindWholeRig, its controller corrected by edsp's LegCompensator
  // (blind_closed_loop.h).
  Generator generator = Generator::kRig;
  std::string config_path;        // nominal model; default: the paper's platform
  double tracker_noise_m = 5e-6;  // 1-σ per axis
  double tracker_rate_hz = 100.0;
  std::vector<MotionDesign> designs = {{"designed", {"calibration"}}, {"six", {"Lz", "Lx", "Rz", "Ry", "M1", "M2"}}};
  std::vector<std::string> held_out = {"Ly", "Rx", "M3", "M4"};
  std::string keep_dir;  // empty: a temporary directory, removed
  bool progress = true;
};

struct DesignScore {
  std::string design;
  double fit_duration_s = 0.0;                    // simulated length of the fit motions
  std::string conclusion;                         // the fit's diagnosis, named ("" when it failed)
  std::vector<std::string> applied;               // effects the kinematics applied
  double before_rms_m = 0.0, before_max_m = 0.0;  // held out, uncalibrated
  double after_rms_m = 0.0, after_max_m = 0.0;    //   and calibrated (measured)
  double predicted_rms_m = 0.0;                   // what the model predicted from the uncalibrated run
  bool met = false;
  std::string error;  // the loop could not be closed (the run or the model refused)
};

struct RigScore {
  int index = 0;
  std::string description;
  double payload_kg = 0.0, rated_payload_kg = 0.0;
  double noise_floor_m = 0.0;        // √3·σ of the tracker noise added
  std::vector<DesignScore> designs;  // in the options' order
};

struct CalibrationBenchmarkResult {
  CalibrationBenchmarkOptions options;
  double rated_payload_kg = 0.0;
  std::vector<RigScore> rigs;
  // Per design, in the options' order.
  std::vector<int> met;
  std::vector<double> median_after_over_floor, median_shrink;
  // Rigs where the first design's calibrated held-out RMS is within 10% of
  // the second's or better (the designed motions against the six).
  int first_as_good = 0;
};

inline constexpr double kCalibrationTargetFloorRatio = 1.5;
inline constexpr double kCalibrationTargetShrink = 0.90;

CalibrationBenchmarkResult RunCalibrationBenchmark(const CalibrationBenchmarkOptions& options);
nlohmann::json ToJson(const CalibrationBenchmarkResult& result);
void PrintCalibrationBenchmark(const CalibrationBenchmarkResult& result);

}  // namespace edsp::gap
