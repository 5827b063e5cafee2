// edsp-gap as users run it: the report JSON keys of interfaces.md §4, a
// saved model evaluated, the report directory, and wrong inputs refused with
// a message that names the file, line and column, and a non-zero exit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_output.h"
#include "edsp/diagnosis/gap_shrink.h"
#include "scratch_dir.h"
#include "edsp/node/build_paths.h"

namespace {

using Output = edsp::test_support::CommandOutput;

Output Gap(const std::string& args) {
  return edsp::test_support::RunCommand(fmt::format("{} {}", edsp::BuiltProgram("edsp-gap"), args));
}

std::string Dir() { return edsp::test_support::ScratchDir("gap_cli"); }

// The paper's platform measured with the controller in `pr_mode` (unsigned:
// a gap the diagnosis finds as passive_rotation).
std::string SimulatedCsv(const std::string& pr_mode = "unsigned", const std::string& motions = "Lz,Rz,M1") {
  const std::string dir = Dir() + "/sim_" + pr_mode + "_" + motions;
  const std::string command = fmt::format(
      "{} rig --config {}/config/huang2021.toml --out {} --motions {} --pr-mode {} "
      "--stops 3 --dwell-s 0.3 --max-speed-m-s 0.25 --max-speed-rad-s 0.5 --tracker-noise-m 5e-6 "
      "--tracker-rate-hz 100 >/dev/null",
      edsp::BuiltProgram("edsp-sim"), edsp::SourceDir(), dir, motions, pr_mode);
  EXPECT_EQ(std::system(command.c_str()), 0);
  return dir + "/measurement.csv";
}

TEST(EdspGapCli, DiagnoseJsonHasTheInterfaceKeysAndAModelThatEvaluates) {
  const std::string csv = SimulatedCsv();
  const std::string model = Dir() + "/model.json", report = Dir() + "/report";
  const Output out =
      Gap(fmt::format("diagnose --config {}/config/huang2021.toml --data {} --json --save-model {} --report {}",
                      edsp::SourceDir(), csv, model, report));
  ASSERT_EQ(out.exit_code, 0) << out.text;
  const nlohmann::json j = nlohmann::json::parse(out.text);
  for (const char* key : {"rms_m", "max_m", "by_run", "by_leg_m", "where"}) EXPECT_TRUE(j["gap"].contains(key)) << key;
  EXPECT_EQ(j["gap"]["by_leg_m"].size(), 6u);
  ASSERT_FALSE(j["effects"].empty());
  for (const char* key : {"name", "params", "explained_fraction", "verdict"})
    EXPECT_TRUE(j["effects"][0].contains(key)) << key;
  EXPECT_EQ(j["effects"][0]["name"], "passive_rotation");
  for (const char* key : {"runs", "before", "after", "shrink", "gap_shrink"}) {
    EXPECT_TRUE(j["holdout"].contains(key)) << key;
  }
  EXPECT_TRUE(j["unexplained"].contains("rms_m"));
  EXPECT_TRUE(j["unexplained"].contains("note"));
  // report.md for people: the verdict first, then the parameters (in
  // engineering units, not JSON), where, and what to do next.
  std::ifstream md(report + "/report.md");
  ASSERT_TRUE(md.good());
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  const std::size_t verdict = text.find("## Verdict"), parameters = text.find("## Parameters"),
                    where = text.find("## Where the gap lies"), next = text.find("## What to do next");
  ASSERT_NE(next, std::string::npos) << text;
  EXPECT_LT(verdict, parameters);
  EXPECT_LT(parameters, where);
  EXPECT_LT(where, next);
  EXPECT_NE(text.find("### `passive_rotation`"), std::string::npos) << text;
  EXPECT_EQ(text.find("{\""), std::string::npos) << "JSON in report.md:\n" << text;

  const Output ev = Gap(fmt::format("evaluate --config {}/config/huang2021.toml --model {} --data {} --json",
                                    edsp::SourceDir(), model, csv));
  ASSERT_EQ(ev.exit_code, 0) << ev.text;
  const nlohmann::json e = nlohmann::json::parse(ev.text);
  EXPECT_GT(e["shrink"].get<double>(), 0.9);
  EXPECT_LT(e["after"]["rms_m"].get<double>(), e["before"]["rms_m"].get<double>());
  // The gap above the noise floor the data show.
  EXPECT_DOUBLE_EQ(e["gap_shrink"].get<double>(),
                   edsp::gap::GapShrink(e["before"]["rms_m"], e["after"]["rms_m"], e["noise_floor_rms_m"]));

  // Rows flagged near a stall are left out, counted, and their share of all
  // the rows given: every fourth row flagged here.
  const std::string flagged = Dir() + "/flagged.csv";
  std::ifstream in(csv);
  std::ofstream out_csv(flagged);
  std::string line;
  std::getline(in, line);
  out_csv << line << "\n";
  int rows = 0, marked = 0;
  for (; std::getline(in, line); ++rows) {
    if (rows % 4 == 0 && line.back() == '0') {
      line.back() = '1';
      ++marked;
    }
    out_csv << line << "\n";
  }
  out_csv.close();
  ASSERT_GT(marked, 10);
  const Output fe = Gap(fmt::format("evaluate --config {}/config/huang2021.toml --model {} --data {} --json",
                                    edsp::SourceDir(), model, flagged));
  ASSERT_EQ(fe.exit_code, 0) << fe.text;
  const nlohmann::json f = nlohmann::json::parse(fe.text);
  EXPECT_EQ(f["timing_excluded_samples"].get<int>(), marked);
  EXPECT_DOUBLE_EQ(f["timing_excluded_share"].get<double>(), static_cast<double>(marked) / rows);
}

// compare: the same motions without and with the correction (here the
// signed PR compensation the diagnosis asks for, run by the controller), per
// motion; each side's figures are what `evaluate` with no model says of
// that measurement alone, and the model's prediction is evaluate's `after`.
TEST(EdspGapCli, CompareGivesEachMotionBeforeAndAfterTheCorrection) {
  const std::string before = SimulatedCsv("unsigned"), after = SimulatedCsv("signed");
  const std::string model = Dir() + "/pr_model.json", plot = Dir() + "/compare";
  const std::string config = fmt::format("{}/config/huang2021.toml", edsp::SourceDir());
  ASSERT_EQ(Gap(fmt::format("diagnose --config {} --data {} --save-model {}", config, before, model)).exit_code, 0);
  const Output out = Gap(fmt::format("compare --config {} --before {} --after {} --model {} --plot {} --json", config,
                                     before, after, model, plot));
  ASSERT_EQ(out.exit_code, 0) << out.text;
  const nlohmann::json c = nlohmann::json::parse(out.text);
  const std::string none = Dir() + "/no_model.json";
  std::ofstream(none) << R"({"format": "edsp-gap-model/1", "effects": []})";
  auto evaluate = [&](const std::string& data, const std::string& m) {
    const Output e = Gap(fmt::format("evaluate --config {} --model {} --data {} --json", config, m, data));
    EXPECT_EQ(e.exit_code, 0) << e.text;
    return nlohmann::json::parse(e.text);
  };
  const nlohmann::json without = evaluate(before, model), with = evaluate(after, none);
  EXPECT_DOUBLE_EQ(c["before"]["rms_m"].get<double>(), without["before"]["rms_m"].get<double>());
  EXPECT_DOUBLE_EQ(c["predicted"]["rms_m"].get<double>(), without["after"]["rms_m"].get<double>());
  EXPECT_DOUBLE_EQ(c["after"]["rms_m"].get<double>(), with["before"]["rms_m"].get<double>());
  ASSERT_EQ(c["motions"].size(), 3u);
  double largest = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const nlohmann::json& m = c["motions"][k];
    EXPECT_EQ(m["run"], without["by_run"][k]["run"]);
    EXPECT_DOUBLE_EQ(m["after"]["rms_m"].get<double>(), with["by_run"][k]["before"]["rms_m"].get<double>());
    // The unsigned PR misses by hundreds of µm on Rz; the signed one by the noise.
    EXPECT_LT(m["after"]["rms_m"].get<double>(), m["before"]["rms_m"].get<double>()) << m.dump();
    largest = std::max(largest, m["before"]["max_m"].get<double>());
  }
  EXPECT_DOUBLE_EQ(largest, c["before"]["max_m"].get<double>());  // the motions partition the samples
  EXPECT_TRUE(c["target_met"].get<bool>()) << c.dump(2);
  std::ifstream dat(plot + "/calibration.dat");
  std::string line;
  int rows = 0;
  while (std::getline(dat, line)) rows += line.empty() || line[0] == '#' ? 0 : 1;
  EXPECT_EQ(rows, 3);
  EXPECT_TRUE(std::ifstream(plot + "/calibration.png").good());

  // The same motions or nothing: a run missing from one side is named.
  const Output mismatch =
      Gap(fmt::format("compare --config {} --before {} --after {}", config, before, SimulatedCsv("signed", "Lz,Rz")));
  EXPECT_NE(mismatch.exit_code, 0);
  EXPECT_NE(mismatch.text.find("run M1 is in the measurement without the calibration"), std::string::npos)
      << mismatch.text;
}

TEST(EdspGapCli, WrongInputsAreNamedWithANonZeroExit) {
  const std::string bad = Dir() + "/bad.csv";
  std::system(("mkdir -p " + Dir()).c_str());
  std::ofstream(bad) << "time_s,run,pose_cmd_x_m,pose_cmd_y_m,pose_cmd_z_m,pose_cmd_roll_rad,pose_cmd_pitch_rad,"
                        "pose_cmd_yaw_rad,leg_cmd_1_m,leg_cmd_2_m,leg_cmd_3_m,leg_cmd_4_m,leg_cmd_5_m,leg_cmd_6_m,"
                        "point_x_m,point_y_m,point_z_m\n"
                        "0,Lz,0,0,1.511,0,0,0,1.9,1.9,1.9,1.9,1.9,1.9,1.2,0,1.5\n"
                        "0.01,Lz,0,0,1.511,0,0,0,1.9,1.9,x1.9,1.9,1.9,1.9,1.2,0,1.5\n";
  Output out = Gap(fmt::format("diagnose --config {}/config/huang2021.toml --data {}", edsp::SourceDir(), bad));
  EXPECT_NE(out.exit_code, 0);
  EXPECT_NE(out.text.find(bad + ":3:"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("\"x1.9\" is not a number"), std::string::npos) << out.text;

  out = Gap(fmt::format("diagnose --config {}/config/huang2021.toml --data /nonexistent.csv", edsp::SourceDir()));
  EXPECT_NE(out.exit_code, 0);
  EXPECT_NE(out.text.find("/nonexistent.csv: cannot open"), std::string::npos) << out.text;

  const std::string model = Dir() + "/broken_model.json";
  std::ofstream(model) << "{\"format\": \"edsp-gap-model/1\", \"effects\": [{\"name\": \"gremlins\", \"theta\": []}]}";
  out = Gap(
      fmt::format("evaluate --config {}/config/huang2021.toml --model {} --data {}", edsp::SourceDir(), model, bad));
  EXPECT_NE(out.exit_code, 0);
  std::ofstream(model) << "{not json";
  out = Gap(fmt::format("evaluate --config {}/config/huang2021.toml --model {} --data {}", edsp::SourceDir(), model,
                        SimulatedCsv()));
  EXPECT_NE(out.exit_code, 0);
  EXPECT_NE(out.text.find("not JSON"), std::string::npos) << out.text;
  std::ofstream(model) << "{\"format\": \"edsp-gap-model/1\", \"effects\": [{\"name\": \"gremlins\", \"theta\": []}]}";
  out = Gap(fmt::format("evaluate --config {}/config/huang2021.toml --model {} --data {}", edsp::SourceDir(), model,
                        SimulatedCsv()));
  EXPECT_NE(out.exit_code, 0);
  EXPECT_NE(out.text.find("unknown effect \"gremlins\""), std::string::npos) << out.text;
}

}  // namespace

namespace {

// The benchmark on the independently written rig: scenario k is of the kind
// its index draws (effect-free, two single, a pair, one outside the
// vocabulary), scored with the issue's targets; an unknown generator or
// encoder choice is refused by name.
TEST(EdspGapCli, BenchmarkOnTheBlindRigScoresEveryKindWithItsTargets) {
  const Output out = Gap("benchmark --generator blind --scenarios 5 --seed 31 --motions Lz,Rz,M1,M2 --json");
  ASSERT_EQ(out.exit_code, 0) << out.text;
  const nlohmann::json j = nlohmann::json::parse(out.text);
  EXPECT_EQ(j["generator"], "blind");
  const std::vector<std::string> kinds = {"none", "single", "single", "pair", "out_of_vocabulary"};
  const std::vector<std::size_t> truths = {0, 1, 1, 2, 1};
  ASSERT_EQ(j["results"].size(), kinds.size());
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    EXPECT_EQ(j["results"][k]["kind"], kinds[k]) << k;
    EXPECT_EQ(j["results"][k]["truth"].size(), truths[k]) << k;
  }
  EXPECT_EQ(j["effect_free"]["scenarios"], 1);
  EXPECT_EQ(j["single_effect"]["scenarios"], 2);
  EXPECT_EQ(j["two_effects"]["scenarios"], 1);
  EXPECT_EQ(j["out_of_vocabulary"]["scenarios"], 1);
  // The effect-free scenario: nothing there, nothing found.
  EXPECT_EQ(j["results"][0]["conclusion"], "none") << j["results"][0].dump();
  ASSERT_EQ(j["targets"].size(), 10u);
  for (const auto& t : j["targets"]) {
    for (const char* key : {"score", "measured", "target", "met"}) EXPECT_TRUE(t.contains(key)) << t.dump();
  }
  EXPECT_EQ(j["whole_rig"]["scenarios"], 0);    // none drawn in this mode
  EXPECT_EQ(j["closed_loop"]["scenarios"], 0);  // the blind rig cannot run edsp's kinematics
  const Output bad = Gap("benchmark --generator sim --scenarios 1");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.text.find("sim"), std::string::npos) << bad.text;
  const Output bad_encoders = Gap("benchmark --generator blind --encoders some --scenarios 1");
  EXPECT_NE(bad_encoders.exit_code, 0);
  EXPECT_NE(bad_encoders.text.find("some"), std::string::npos) << bad_encoders.text;
}

// A whole rig of every class on the blind rig: static, play, compliance, a
// soft servo loop and screws warming, all in the truth; every true effect
// either identified or shown to be below what the runs can tell, and the
// three whole-rig targets scored on it.
TEST(EdspGapCli, WholeRigModeDrawsEveryClassAndSaysWhatTheRunsCannotShow) {
  const Output out =
      Gap("benchmark --mode whole --generator blind --scenarios 1 --seed 31 --motions Lz,Rz,M1,M2 --json");
  ASSERT_EQ(out.exit_code, 0) << out.text;
  const nlohmann::json j = nlohmann::json::parse(out.text);
  EXPECT_EQ(j["mode"], "whole");
  ASSERT_EQ(j["results"].size(), 1u);
  const nlohmann::json& r = j["results"][0];
  EXPECT_EQ(r["kind"], "whole_rig");
  for (const char* effect : {"leg_offset", "joint_position", "lead_error", "periodic_lead_error", "backlash",
                             "compliance", "servo_lag", "thermal_drift"}) {
    EXPECT_NE(std::find(r["truth"].begin(), r["truth"].end(), effect), r["truth"].end()) << effect << r.dump();
  }
  // Each true effect is identified, missed though the runs show it, or
  // below what they show: one of the three, never two.
  for (const auto& t : r["truth"]) {
    const auto in = [&](const nlohmann::json& list) { return std::find(list.begin(), list.end(), t) != list.end(); };
    const bool identified = in(r["identified"]);
    EXPECT_EQ(int{identified} + int{in(r["missed"]["shown"])} + int{in(r["missed"]["below_what_the_runs_show"])}, 1)
        << t << ": " << r.dump();
  }
  EXPECT_EQ(j["whole_rig"]["scenarios"], 1);
  EXPECT_EQ(j["whole_rig"]["all_shown_named"], r["missed"]["shown"].empty() ? 1 : 0);
  int whole_targets = 0;
  for (const auto& t : j["targets"]) whole_targets += t["score"].get<std::string>().rfind("whole_rig_", 0) == 0;
  EXPECT_EQ(whole_targets, 3);
}

// Changes within a session on the blind rig, one of each kind the mode
// draws (a leg's step, the tracker knocked, screws warming, no change):
// both steps found as events of their kind within a second, none on the
// drift or the unchanged rig, and the mode refuses edsp's rig by name.
// --keep leaves each scenario's data and diagnosis, the events the score
// read; a directory it cannot write stops the run, named.
TEST(EdspGapCli, EventsBenchmarkFindsEachStepAndNoEventWhereNothingStepped) {
  const std::string kept = Dir() + "/events";
  const Output out = Gap("benchmark --mode events --scenarios 4 --seed 61 --motions Lz,Rz,M1,M2 --json --keep " + kept);
  ASSERT_EQ(out.exit_code, 0) << out.text;
  const nlohmann::json j = nlohmann::json::parse(out.text);
  EXPECT_EQ(j["mode"], "events");
  ASSERT_EQ(j["scenarios"].size(), 4u);
  const std::vector<std::string> kinds = {"leg_step", "tracker_step", "drift", "none"};
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    const nlohmann::json& s = j["scenarios"][k];
    EXPECT_EQ(s["kind"], kinds[k]);
    EXPECT_FALSE(s.contains("error")) << s.dump();
    if (k < 2) {
      EXPECT_TRUE(s["detected"].get<bool>()) << s.dump();
      EXPECT_TRUE(s["timed"].get<bool>()) << s.dump();
    } else {
      EXPECT_TRUE(s["events"].empty()) << s.dump();
    }
    EXPECT_EQ(s["false_events"], 0) << s.dump();
    const std::string dir = fmt::format("{}/scenario-{:03d}", kept, k);
    std::ifstream diagnosis(dir + "/diagnosis.json");
    ASSERT_TRUE(diagnosis) << dir;
    EXPECT_EQ(nlohmann::json::parse(diagnosis)["events"].size(), s["events"].size()) << dir;
    EXPECT_TRUE(std::ifstream(dir + "/data.csv").good()) << dir;
  }
  EXPECT_EQ(j["steps"], 2);
  EXPECT_EQ(j["detected"], 2);
  EXPECT_EQ(j["unchanged_with_event"], 0);
  EXPECT_EQ(j["drifts_as_steps"], 0);
  const Output bad = Gap("benchmark --mode events --generator rig --scenarios 1");
  EXPECT_EQ(bad.exit_code, 1) << bad.text;
  EXPECT_NE(bad.text.find("--mode events --generator rig"), std::string::npos) << bad.text;
  const Output unwritable = Gap("benchmark --mode events --scenarios 1 --seed 61 --motions Lz --keep /proc/edsp-kept");
  EXPECT_NE(unwritable.exit_code, 0) << unwritable.text;
  EXPECT_NE(unwritable.text.find("/proc/edsp-kept"), std::string::npos) << unwritable.text;
}

// The closed loop on edsp's rig: scenario 1 (one effect) is measured again
// on motions no fit saw, without and with its saved model applied by the
// kinematics. The calibration must close most of the gap above the
// tracker's noise (7 µm, not the default, so σ is read from the run), as
// the model predicted from the uncalibrated run; the effect-free scenario 0
// does not count.
TEST(EdspGapCli, BenchmarkClosesTheLoopOnTheRigAndSetsTheMeasuredShrinkBesideThePrediction) {
  const Output out =
      Gap("benchmark --scenarios 2 --seed 77 --motions Lz,Lx,Rz,Ry,M1,M2 --closed-loop-motions Ly,M9 --noise-m 7e-6 "
          "--json");
  ASSERT_EQ(out.exit_code, 0) << out.text;
  const nlohmann::json j = nlohmann::json::parse(out.text);
  EXPECT_EQ(j["closed_loop"]["motions"], (std::vector<std::string>{"Ly", "M9"}));
  EXPECT_EQ(j["closed_loop"]["scenarios"], 1);
  const nlohmann::json& loop = j["results"][1]["closed_loop"];
  ASSERT_TRUE(loop.is_object()) << j["results"][1].dump(2);
  const double before = loop["before_rms_m"], after = loop["after_rms_m"], predicted = loop["predicted_after_rms_m"];
  EXPECT_NEAR(after, predicted, 0.1 * before) << loop.dump(2);
  EXPECT_DOUBLE_EQ(j["closed_loop"]["median_measured_shrink"].get<double>(), loop["shrink"].get<double>());
  // The gap is what lies above the rig tracker's own noise, σ as set.
  const double sigma = j["tracker_noise_m"];
  EXPECT_EQ(sigma, 7e-6);
  EXPECT_EQ(j["results"][1]["noise_sigma_m"].get<double>(), sigma);
  EXPECT_DOUBLE_EQ(loop["gap_shrink"].get<double>(), edsp::gap::GapShrink(before, after, std::sqrt(3.0) * sigma));
  EXPECT_GT(loop["gap_shrink"].get<double>(), 0.8) << loop.dump(2);
  EXPECT_DOUBLE_EQ(loop["predicted_gap_shrink"].get<double>(),
                   edsp::gap::GapShrink(before, predicted, std::sqrt(3.0) * sigma));
  EXPECT_DOUBLE_EQ(j["closed_loop"]["median_measured_gap_shrink"].get<double>(), loop["gap_shrink"].get<double>());
  EXPECT_DOUBLE_EQ(j["closed_loop"]["median_predicted_gap_shrink"].get<double>(),
                   loop["predicted_gap_shrink"].get<double>());
  const bool apart = std::abs(loop["gap_shrink"].get<double>() - loop["predicted_gap_shrink"].get<double>()) >= 0.10;
  EXPECT_EQ(j["closed_loop"]["disagree_by_10_gap_points"].size(), apart ? 1u : 0u) << j["closed_loop"].dump();

  const Output off = Gap("benchmark --scenarios 1 --seed 77 --motions Lz,Rz --closed-loop-motions none --json");
  ASSERT_EQ(off.exit_code, 0) << off.text;
  EXPECT_FALSE(nlohmann::json::parse(off.text)["results"][0].contains("closed_loop"));
}

}  // namespace
