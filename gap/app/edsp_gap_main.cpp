// edsp-gap: diagnose the sim-to-real gap (docs/diagnosis.md).
//   edsp-gap diagnose --config C --data D [--data D2 …] [--json] [--save-model M] [--report DIR]
//                     [--keep-timing-events]
//   edsp-gap evaluate --config C --model M --data T [--json] [--keep-timing-events]
//   edsp-gap compare --config C --before B --after A [--model M [--apply-ambiguous]] [--plot DIR] [--json]
//                    [--keep-timing-events]
//   edsp-gap benchmark --scenarios N --seed S [--generator rig|blind] [--motions Lz,…] [--json] [--noise-m 5e-6]
//                      [--keep DIR] [--closed-loop-motions Ly,Rx,M9|none] [--encoders drawn|with|without]
//   edsp-gap drift --config C --baseline M --data D [--data D2 …] [--recorded with|without] [--threshold-m X]
//                  [--apply-ambiguous] [--json]
//   edsp-gap benchmark --mode calibration --scenarios N --seed S [--generator rig|blind] [--held-out Ly,Rx,M3,M4]
//                      [--noise-m 5e-6] [--json] [--keep DIR]   (whole rigs: docs/calibration.md)
//   edsp-gap benchmark --mode drift --scenarios N --seed S [--noise-m 5e-6] [--session-motions Lz,…] [--json]
//                      (drift on whole rigs)
//   edsp-gap benchmark --mode events --scenarios N --seed S [--motions …] [--json] [--keep DIR]
//                      (changes within a session)
//   edsp-gap benchmark --mode whole --scenarios N --seed S [--generator rig|blind] [--json]
//                      (whole rigs of every class, scored as effects)
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <initializer_list>
#include <map>
#include <string>
#include <type_traits>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/gap/benchmark.h"
#include "edsp/gap/calibration_benchmark.h"
#include "edsp/diagnosis/calibration_check.h"
#include "edsp/diagnosis/drift.h"
#include "edsp/gap/drift_benchmark.h"
#include "edsp/gap/events_benchmark.h"
#include "edsp/diagnosis/gap_shrink.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/runtime.h"

namespace edsp::gap {
namespace {

// --recorded: whether the baseline was applied while the new session was
// recorded, or as the data's leg_corr columns say.
enum class Recorded { kAuto, kWith, kWithout };
// --mode of benchmark.
enum class BenchmarkMode { kEffects, kCalibration, kDrift, kEvents, kWhole };

// The words of an enum whose names its library gives: one table.
template <typename E>
std::map<std::string, E> WordsOf(std::initializer_list<E> values, const char* (*name)(E)) {
  std::map<std::string, E> words;
  for (E value : values) words.emplace(name(value), value);
  return words;
}

const std::map<std::string, Against> kAgainstWords = WordsOf({Against::kNominal, Against::kCalibration}, AgainstName);
const std::map<std::string, Recorded> kRecordedWords = {
    {"auto", Recorded::kAuto}, {"with", Recorded::kWith}, {"without", Recorded::kWithout}};
const std::map<std::string, BenchmarkMode> kModeWords = {{"effects", BenchmarkMode::kEffects},
                                                         {"calibration", BenchmarkMode::kCalibration},
                                                         {"drift", BenchmarkMode::kDrift},
                                                         {"events", BenchmarkMode::kEvents},
                                                         {"whole", BenchmarkMode::kWhole}};
const std::map<std::string, Generator> kGeneratorWords = WordsOf({Generator::kRig, Generator::kBlind}, GeneratorName);
const std::map<std::string, EncoderColumns> kEncoderWords =
    WordsOf({EncoderColumns::kDrawn, EncoderColumns::kWith, EncoderColumns::kWithout}, EncoderColumnsName);

// An option whose words stand for an enum's values: the help lists the
// words, and a word not among them is refused, named.
template <typename E>
CLI::Option* AddChoice(CLI::App* c, const std::string& name, E* target, const std::map<std::string, E>& words,
                       const std::string& help) {
  std::string list;
  for (const auto& entry : words) list += (list.empty() ? "" : ",") + entry.first;
  list = "{" + list + "}";
  const CLI::Validator word(
      [words, list](std::string& input) -> std::string {
        const auto it = words.find(input);
        if (it == words.end()) return "'" + input + "' is not one of " + list;
        input = std::to_string(static_cast<std::underlying_type_t<E>>(it->second));  // what CLI11 reads an enum from
        return "";
      },
      list);
  return c->add_option(name, *target, help)->transform(word)->type_name("TEXT");
}

template <typename E>
std::string WordOf(const std::map<std::string, E>& words, E value) {
  for (const auto& [word, v] : words) {
    if (v == value) return word;
  }
  return "";
}

MeasurementData LoadAll(const std::vector<std::string>& paths, TimingEvents timing = TimingEvents::kLeaveOut) {
  MeasurementData data;
  for (const std::string& path : paths) AppendMeasurement(&data, LoadMeasurement(path, timing));
  return data;
}

nlohmann::json LoadModelFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MeasurementError(path + ": cannot open");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw MeasurementError(fmt::format("{}: not JSON at byte {}: {}", path, e.byte, e.what()));
  }
}

std::string CalibrationEffectsText(const CalibrationResult& c) {
  std::string text;
  for (Effect e : c.effects) text += (text.empty() ? "" : ", ") + std::string(EffectName(e));
  return text.empty() ? "nothing" : text;
}

void PrintText(const Diagnosis& d) {
  std::printf("gap before any effect: %.1f µm RMS, %.1f µm max over %d samples in %zu runs\n",
              d.gap.overall.rms_m * 1e6, d.gap.overall.max_m * 1e6, d.samples, d.runs.size());
  if (d.timing_excluded > 0) {
    std::printf("left out: %lld samples the data flags timing_event (near a stall of its real-time system)\n",
                static_cast<long long>(d.timing_excluded));
  }
  if (const std::string recorded = RecordedCorrectionText(d); !recorded.empty()) std::printf("%s\n", recorded.c_str());
  std::printf("changes within the session: %s\n", ChangesText(d).c_str());
  std::printf("%s\n\n", d.gap.where.c_str());
  std::printf("%-4s %-20s %-11s %9s %9s  %s\n", "rank", "effect", "verdict", "explained", "cv gain", "with");
  for (std::size_t k = 0; k < d.effects.size(); ++k) {
    const EffectResult& r = d.effects[k];
    std::printf("%-4zu %-20s %-11s %9s %9s  %s\n", k + 1, EffectName(r.effect), VerdictName(r.verdict),
                Percent(r.explained_fraction).c_str(), Percent(r.cv_gain).c_str(),
                fmt::format("{}", fmt::join(AmbiguousWithNames(r), ", ")).c_str());
  }
  std::printf("\nconclusion: %s\n", ConclusionName(d.conclusion));
  std::printf("held-out runs: before %.1f µm RMS, after %.1f µm RMS, shrink %.0f%% (noise floor %.1f µm, %s)\n",
              d.holdout_before.rms_m * 1e6, d.holdout_after.rms_m * 1e6, 100 * d.shrink, d.noise_floor_rms_m * 1e6,
              GapShrinkText(d.holdout_before.rms_m, d.noise_floor_rms_m, d.gap_shrink).c_str());
  std::printf("calibration applies: %s (held out %.1f µm RMS; the identified effects alone %.1f µm; chosen: %s)\n",
              CalibrationEffectsText(d.calibration).c_str(), d.calibration.heldout_rms_m * 1e6,
              d.calibration.identified_heldout_rms_m * 1e6, ChosenByName(d.calibration.chosen_by));
  std::printf("left: %s\n", d.unexplained_note.c_str());
  std::printf("tracker clock: %s\n", TrackerClockNote(d).c_str());
}

// Each subcommand: its arguments, how they are declared, and what it does.

struct DiagnoseArgs {
  std::string config, save_model, report_dir;
  std::vector<std::string> data;
  bool json = false, keep_timing_events = false;
  DiagnoseOptions options;
  CLI::Option* thermal_tau = nullptr;
};

struct EvaluateArgs {
  std::string config, model;
  std::vector<std::string> data;
  bool json = false, keep_timing_events = false;
};

struct DriftArgs {
  std::string config, baseline;
  Recorded recorded = Recorded::kAuto;
  std::vector<std::string> data;
  DriftOptions options;
  bool json = false;
};

struct CompareArgs {
  std::string config, model, plot_dir;
  std::vector<std::string> before, after;
  bool apply_ambiguous = false, json = false, keep_timing_events = false;
};

TimingEvents TimingOf(bool keep) { return keep ? TimingEvents::kKeep : TimingEvents::kLeaveOut; }

struct BenchmarkArgs {
  BenchmarkOptions bench;
  BenchmarkMode mode = BenchmarkMode::kEffects;
  std::vector<std::string> held_out = CalibrationBenchmarkOptions{}.held_out;
  std::vector<std::string> session_motions = DriftBenchmarkOptions{}.session_motions;
  std::string keep_dir;
  bool json = false;
  const CLI::Option* generator = nullptr;  // to tell --generator and --motions given from their defaults
  const CLI::Option* motions = nullptr;
};

constexpr char kKeepTimingEventsHelp[] =
    "keep the rows flagged timing_event (near a stall of the real-time system; left out by default)";

CLI::App* AddDiagnose(CLI::App& app, DiagnoseArgs* a) {
  CLI::App* c = app.add_subcommand("diagnose", "diagnose measured data against the config's model");
  c->add_option("--config", a->config, "platform config (TOML)")->required();
  c->add_option("--data", a->data, "measurement CSV (interfaces.md §3) or edsp LCM log; repeatable")->required();
  c->add_flag("--json", a->json, "print the JSON report (interfaces.md §4)");
  c->add_option("--save-model", a->save_model, "write the selected effects for `evaluate`");
  c->add_option("--report", a->report_dir, "write report.md with PNG plots here");
  c->add_flag("--keep-timing-events", a->keep_timing_events, kKeepTimingEventsHelp);
  c->add_option("--max-rate-hz", a->options.max_rate_hz, "thin each run to this rate")->check(CLI::Range(1.0, 10000.0));
  AddChoice(c, "--against", &a->options.against, kAgainstWords,
            "data recorded with a calibration in force: nominal (the rig's whole effects; a model saved replaces "
            "the calibration) or calibration (what it leaves)");
  a->thermal_tau = c->add_option("--thermal-time-constant-s", a->options.design.thermal_time_constant_s,
                                 "the screws' cooling time, fixed (default: estimated when thermal drift is found)")
                       ->check(CLI::Range(1.0, 1e6));
  c->add_option("--structural-mode-hz", a->options.design.structural_mode_hz,
                "the structural mode's frequency, fixed (a tap test's; default: searched 1-25 Hz)")
      ->check(CLI::Range(0.5, 100.0));
  c->add_option("--structural-mode-damping", a->options.design.structural_mode_damping,
                "its damping ratio with --structural-mode-hz (default 0.03)")
      ->check(CLI::Range(0.001, 1.0));
  return c;
}

CLI::App* AddEvaluate(CLI::App& app, EvaluateArgs* a) {
  CLI::App* c = app.add_subcommand("evaluate", "apply a saved model to data it has never seen");
  c->add_option("--config", a->config, "platform config (TOML)")->required();
  c->add_option("--model", a->model, "model saved by diagnose --save-model")->required();
  c->add_option("--data", a->data, "measurement CSV or edsp LCM log; repeatable")->required();
  c->add_flag("--json", a->json, "print JSON");
  c->add_flag("--keep-timing-events", a->keep_timing_events, kKeepTimingEventsHelp);
  return c;
}

CLI::App* AddDrift(CLI::App& app, DriftArgs* a) {
  CLI::App* c = app.add_subcommand("drift", "what changed on the rig since a calibration, and whether to recalibrate");
  c->add_option("--config", a->config, "platform config (TOML)")->required();
  c->add_option("--baseline", a->baseline, "the calibration in force (diagnose --save-model)")->required();
  c->add_option("--data", a->data, "a new session's measurement CSV or edsp LCM log; repeatable")->required();
  AddChoice(c, "--recorded", &a->recorded, kRecordedWords,
            "with: the kinematics applied the baseline while it was recorded (usual); "
            "without: it ran on the nominal model; auto (default): as the data's "
            "leg_corr columns say, with where it has none");
  c->add_option("--threshold-m", a->options.threshold_m,
                "recalibrate when the baseline leaves more than this RMS (default: 1.5× the data's noise floor)")
      ->check(CLI::Range(0.0, 0.01));
  c->add_flag("--apply-ambiguous", a->options.apply_ambiguous,
              "the kinematics applied the baseline's ambiguous effects too");
  c->add_flag("--json", a->json, "print JSON");
  return c;
}

CLI::App* AddCompare(CLI::App& app, CompareArgs* a) {
  CLI::App* c = app.add_subcommand(
      "compare", "the same motions measured without and with a calibration: point A's error per motion");
  c->add_option("--config", a->config, "platform config (TOML)")->required();
  c->add_option("--before", a->before, "measurement without the calibration (CSV or LCM log); repeatable")->required();
  c->add_option("--after", a->after, "the same motions with the calibration applied; repeatable")->required();
  c->add_option("--model", a->model, "the calibration's model: its prediction from --before, beside");
  c->add_flag("--apply-ambiguous", a->apply_ambiguous,
              "the controller applied the model's ambiguous effects too (predict with them)");
  c->add_option("--plot", a->plot_dir, "write calibration.png (and its data and gnuplot script) here");
  c->add_flag("--json", a->json, "print JSON");
  c->add_flag("--keep-timing-events", a->keep_timing_events, kKeepTimingEventsHelp);
  return c;
}

CLI::App* AddBenchmark(CLI::App& app, BenchmarkArgs* a) {
  BenchmarkOptions& bench = a->bench;
  CLI::App* c = app.add_subcommand("benchmark", "score the diagnosis blind on virtual-rig scenarios");
  c->add_option("--scenarios", bench.scenarios, "how many")->check(CLI::Range(1, 100000));
  c->add_option("--seed", bench.seed, "scenario draw seed");
  c->add_option("--config", bench.config_path, "nominal platform config");
  c->add_option("--noise-m", bench.tracker_noise_m, "tracker noise, 1-σ per axis")->check(CLI::Range(0.0, 1e-3));
  a->generator = AddChoice(c, "--generator", &bench.generator, kGeneratorWords,
                           "rig: edsp's own virtual rig; blind: the independently written rig (blindrig/), "
                           "out-of-vocabulary scenarios and its own tracker draws");
  AddChoice(c, "--encoders", &bench.encoders, kEncoderWords,
            "blind generator: encoder columns as drawn, in every scenario, or in none");
  a->motions = c->add_option("--motions", bench.motions, "motions of every scenario, comma-separated")->delimiter(',');
  c->add_option("--closed-loop-motions", bench.closed_loop_motions,
                "rig generator: motions no fit saw, run without and with the model applied (\"none\": skip)")
      ->delimiter(',');
  AddChoice(c, "--mode", &a->mode, kModeWords,
            "effects: which effect the diagnosis names; calibration: the loop closed on whole rigs, "
            "designed motions against six; drift: what edsp-gap drift names on rigs that "
            "changed or not "
            "(--scenarios rigs); events: changes within a session found as events, on the blind rig; "
            "whole: every scenario a whole rig of every class (static, dynamic, thermal), scored as effects");
  c->add_option("--held-out", a->held_out, "calibration mode: motions no fit sees, comma-separated")->delimiter(',');
  c->add_option("--session-motions", a->session_motions,
                "drift mode: the motions of the sessions after the calibration, comma-separated")
      ->delimiter(',');
  c->add_option("--keep", a->keep_dir, "keep each scenario's data and report here");
  c->add_flag("--json", a->json, "print JSON");
  return c;
}

int RunDiagnose(DiagnoseArgs a) {
  if (a.thermal_tau->count() > 0) a.options.thermal_time_constants_s.clear();
  const PlatformModel model(LoadConfigFile(a.config));
  const MeasurementData data = LoadAll(a.data, TimingOf(a.keep_timing_events));
  if (!a.save_model.empty() && a.options.against == Against::kCalibration && CarriesACorrection(data)) {
    // Its effects are increments: applied alone they would replace the
    // calibration they were measured on instead of adding to it.
    throw std::runtime_error(fmt::format(
        "--save-model with --against calibration: {} was recorded with a calibration in force, and a model of what "
        "it leaves would replace it in the kinematics, not add to it; diagnose --against nominal (the default) to "
        "save the rig's whole calibration",
        data.source));
  }
  const Diagnosis d = Diagnose(model, data, a.options);
  if (!a.save_model.empty()) {
    std::ofstream out(a.save_model);
    out << ModelJson(d).dump(2) << "\n";
    if (!out) throw std::runtime_error(a.save_model + ": cannot write the model");
  }
  if (!a.report_dir.empty()) WriteReport(d, a.report_dir);
  if (a.json)
    std::printf("%s\n", ToJson(d).dump(2).c_str());
  else
    PrintText(d);
  return 0;
}

int RunEvaluate(const EvaluateArgs& a) {
  const PlatformModel model(LoadConfigFile(a.config));
  const MeasurementData data = LoadAll(a.data, TimingOf(a.keep_timing_events));
  const Evaluation ev = Evaluate(model, data, LoadModelFile(a.model), a.model);
  if (a.json) {
    std::printf("%s\n", ToJson(ev).dump(2).c_str());
  } else {
    std::printf(
        "before %.1f µm RMS (%.1f max), after %.1f µm RMS (%.1f max), shrink %.0f%% (noise floor %.1f µm, %s)\n",
        ev.before.rms_m * 1e6, ev.before.max_m * 1e6, ev.after.rms_m * 1e6, ev.after.max_m * 1e6, 100 * ev.shrink,
        ev.noise_floor_rms_m * 1e6, GapShrinkText(ev.before.rms_m, ev.noise_floor_rms_m, ev.gap_shrink).c_str());
    if (ev.against_nominal) {
      std::printf(
          "the data was recorded with a calibration in force, which the model replaces: both figures are "
          "against the nominal model\n");
    }
    if (ev.timing_excluded > 0) {
      std::printf("left out: %lld samples the data flags timing_event (%.1f%%)\n",
                  static_cast<long long>(ev.timing_excluded), 100 * ev.timing_excluded_share);
    }
  }
  return 0;
}

// --recorded: with, without, or auto: as the data's leg_corr columns say
// (several files are one session: any correction in them says "with"), and
// "with" for data without the columns, the usual case.
bool RecordedWithBaseline(Recorded choice, const MeasurementData& data) {
  if (choice != Recorded::kAuto) return choice == Recorded::kWith;
  return !data.has_correction || CarriesACorrection(data);
}

int RunDrift(DriftArgs a) {
  const PlatformModel model(LoadConfigFile(a.config));
  const MeasurementData data = LoadAll(a.data);
  a.options.recorded_with_baseline = RecordedWithBaseline(a.recorded, data);
  const DriftReport r = Drift(model, LoadModelFile(a.baseline), a.baseline, data, a.options);
  if (a.json)
    std::printf("%s\n", ToJson(r).dump(2).c_str());
  else
    std::printf("%s", DriftText(r).c_str());
  return 0;
}

int RunCompare(const CompareArgs& a) {
  const PlatformModel model(LoadConfigFile(a.config));
  const bool predicted = !a.model.empty();
  // Predicted from what the kinematics applied: identified effects, the
  // ambiguous ones only with --apply-ambiguous.
  const MeasurementData before = LoadAll(a.before, TimingOf(a.keep_timing_events));
  const nlohmann::json applied =
      predicted ? AppliedModelJson(LoadModelFile(a.model), a.apply_ambiguous) : EmptyModelJson();
  const Evaluation without = Evaluate(model, before, applied, predicted ? a.model : "no model");
  const Evaluation with =
      Evaluate(model, LoadAll(a.after, TimingOf(a.keep_timing_events)), EmptyModelJson(), "no model");
  const CalibrationCheck check = CheckCalibration(without, with, predicted);
  if (!a.plot_dir.empty()) {
    std::filesystem::create_directories(a.plot_dir);
    const std::string png = WriteCheckPlot(check, a.plot_dir);
    if (!a.json) std::printf("%s\n", png.empty() ? "gnuplot wrote no plot" : png.c_str());
  }
  if (a.json)
    std::printf("%s\n", ToJson(check).dump(2).c_str());
  else
    std::printf("%s", CheckTable(check).c_str());
  return 0;
}

// Drift closes the loop through edsp's kinematics on edsp's rig only.
void RequireEdspRig(const BenchmarkArgs& a) {
  if (a.bench.generator == Generator::kRig) return;
  throw std::invalid_argument("benchmark --mode " + WordOf(kModeWords, a.mode) + " --generator " +
                              GeneratorName(a.bench.generator) +
                              ": drift is scored on edsp's rig only (--generator rig)");
}

template <typename Result, typename Print>
int Emit(const Result& result, bool json, Print print) {
  if (json)
    std::printf("%s\n", ToJson(result).dump(2).c_str());
  else
    print(result);
  return 0;
}

// Whole rigs, each motion design's calibration closed on held-out motions.
int RunCalibrationBenchmarkCommand(const BenchmarkArgs& a) {
  CalibrationBenchmarkOptions o;
  o.generator = a.bench.generator;
  o.rigs = a.bench.scenarios;
  o.seed = a.bench.seed;
  o.config_path = a.bench.config_path;
  o.tracker_noise_m = a.bench.tracker_noise_m;
  o.held_out = a.held_out;
  o.keep_dir = a.keep_dir;
  o.progress = !a.json || isatty(fileno(stderr));
  return Emit(RunCalibrationBenchmark(o), a.json, PrintCalibrationBenchmark);
}

// Whole rigs calibrated, then measured again unchanged and changed.
int RunDriftBenchmarkCommand(const BenchmarkArgs& a) {
  RequireEdspRig(a);
  DriftBenchmarkOptions o;
  o.rigs = a.bench.scenarios;
  o.seed = a.bench.seed;
  o.config_path = a.bench.config_path;
  o.tracker_noise_m = a.bench.tracker_noise_m;
  o.session_motions = a.session_motions;
  o.progress = !a.json || isatty(fileno(stderr));
  return Emit(RunDriftBenchmark(o), a.json, PrintDriftBenchmark);
}

// Rigs that change within a session (or not), on the blind rig.
int RunEventsBenchmarkCommand(const BenchmarkArgs& a) {
  if (a.generator != nullptr && a.generator->count() > 0 && a.bench.generator != Generator::kBlind) {
    throw std::invalid_argument(std::string("benchmark --mode events --generator ") + GeneratorName(a.bench.generator) +
                                ": events are scored on the blind rig only (--generator blind)");
  }
  EventsBenchmarkOptions o;
  o.scenarios = a.bench.scenarios;
  o.seed = a.bench.seed;
  o.config_path = a.bench.config_path;
  if (a.motions != nullptr && a.motions->count() > 0) o.motions = a.bench.motions;
  o.keep_dir = a.keep_dir;
  o.progress = !a.json || isatty(fileno(stderr));
  return Emit(RunEventsBenchmark(o), a.json, PrintEventsBenchmark);
}

int RunBenchmarkCommand(BenchmarkArgs a) {
  switch (a.mode) {
    case BenchmarkMode::kCalibration: return RunCalibrationBenchmarkCommand(a);
    case BenchmarkMode::kEvents: return RunEventsBenchmarkCommand(a);
    case BenchmarkMode::kDrift: return RunDriftBenchmarkCommand(a);
    case BenchmarkMode::kEffects:
    case BenchmarkMode::kWhole: break;
  }
  a.bench.keep_dir = a.keep_dir;
  a.bench.whole_rigs = a.mode == BenchmarkMode::kWhole;
  if (a.bench.closed_loop_motions == std::vector<std::string>{"none"}) a.bench.closed_loop_motions.clear();
  a.bench.progress = !a.json || isatty(fileno(stderr));
  const BenchmarkResult result = RunBenchmark(a.bench);
  if (a.json)
    std::printf("%s\n", ToJson(result).dump(2).c_str());
  else
    PrintBenchmark(result);
  return 0;
}

int Run(int argc, char** argv) {
  CLI::App app{
      "edsp-gap: where the model and the measured platform part, which effect causes it, how far "
      "the gap shrinks once it is modelled"};
  app.require_subcommand(1);
  DiagnoseArgs diagnose;
  EvaluateArgs evaluate;
  CompareArgs compare;
  DriftArgs drift;
  BenchmarkArgs benchmark;
  const CLI::App* diagnose_command = AddDiagnose(app, &diagnose);
  const CLI::App* evaluate_command = AddEvaluate(app, &evaluate);
  const CLI::App* compare_command = AddCompare(app, &compare);
  const CLI::App* drift_command = AddDrift(app, &drift);
  AddBenchmark(app, &benchmark);
  CLI11_PARSE(app, argc, argv);
  if (*diagnose_command) return RunDiagnose(diagnose);
  if (*evaluate_command) return RunEvaluate(evaluate);
  if (*compare_command) return RunCompare(compare);
  if (*drift_command) return RunDrift(drift);
  return RunBenchmarkCommand(benchmark);
}

}  // namespace
}  // namespace edsp::gap

int main(int argc, char** argv) { return edsp::RunMain("edsp-gap", edsp::gap::Run, argc, argv); }
