// edsp-cueing as a simulator engineer runs it: every shipped manoeuvre
// through classical washout on the paper's platform stays inside every
// limit, its JSON matches the library, and a bad file is named.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_output.h"
#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/cueing_run.h"
#include "edsp/cueing/manoeuvre_variants.h"
#include "edsp/cueing/omct.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/build_paths.h"
#include "scratch_dir.h"

namespace edsp {
namespace {

std::string Manoeuvres() {
  std::string list;
  for (const auto& entry : std::filesystem::directory_iterator(SourceDir() + "/config/manoeuvres")) {
    list += " --manoeuvre " + entry.path().string();
  }
  return list;
}

test_support::CommandOutput RunCueing(const std::string& arguments) {
  return test_support::RunCommand(BuiltProgram("edsp-cueing") + " " + arguments);
}

const std::string kConfigs =
    " --config " + SourceDir() + "/config/huang2021.toml --cueing " + SourceDir() + "/config/cueing.toml";

TEST(EdspCueingCli, EveryShippedManoeuvreStaysInsideEveryLimitAndItsJsonMatchesTheLibrary) {
  const auto run = RunCueing("offline" + kConfigs + Manoeuvres() + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.text;
  const auto out = nlohmann::json::parse(run.text);
  EXPECT_EQ(out["algorithm"], "classical_washout");
  EXPECT_EQ(out["limit_violations"], 0) << run.text;
  ASSERT_GE(out["manoeuvres"].size(), 7u);
  const PlatformModel model(LoadConfigFile(SourceDir() + "/config/huang2021.toml"));
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  double sum = 0.0;
  for (const auto& m : out["manoeuvres"]) {
    const CueingRun library =
        RunCueing(model, config, CueingAlgorithm::kClassicalWashout, LoadManoeuvre(m["file"].get<std::string>()));
    EXPECT_DOUBLE_EQ(m["perception_error"].get<double>(), library.score.overall) << m["name"];
    EXPECT_EQ(m["limit_violations"], 0) << m.dump();
    EXPECT_GT(m["peak_stroke_used"].get<double>(), 0.0) << m["name"];
    EXPECT_LT(m["peak_stroke_used"].get<double>(), 1.0) << m["name"];
    for (const char* channel : {"fx", "fy", "fz", "wx", "wy", "wz"}) {
      EXPECT_TRUE(m["channels"][channel]["rms_error"].is_number()) << m["name"] << " " << channel;
    }
    sum += library.score.overall;
  }
  EXPECT_NEAR(out["perception_error"].get<double>(), sum / static_cast<double>(out["manoeuvres"].size()), 1e-12);
}

TEST(EdspCueingCli, OnARigItScoresTheRealMotionBesideTheCommanded) {
  const auto run = RunCueing("offline" + kConfigs + " --manoeuvre " + SourceDir() +
                             "/config/manoeuvres/braking.toml --json --rig-effects " + SourceDir() +
                             "/config/huang2021-rig-effects.toml");
  ASSERT_EQ(run.exit_code, 0) << run.text;
  const auto out = nlohmann::json::parse(run.text);
  const auto& braking = out["manoeuvres"][0];
  ASSERT_TRUE(braking["real"]["perception_error"].is_number()) << run.text;
  EXPECT_DOUBLE_EQ(out["perception_error_real"].get<double>(), braking["real"]["perception_error"].get<double>());
  // The example rig follows within micrometres: a rider feels its
  // commands, within a percent.
  EXPECT_NEAR(braking["real"]["perception_error"].get<double>(), braking["perception_error"].get<double>(),
              0.01 * braking["perception_error"].get<double>());
  EXPECT_TRUE(braking["real"]["channels"]["fx"]["delay_s"].is_number());
}

TEST(EdspCueingCli, OmctJsonHasEveryChannelAtEveryFrequencyAsTheLibraryMeasures) {
  const auto run = RunCueing("omct" + kConfigs + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.text;
  const auto out = nlohmann::json::parse(run.text);
  const PlatformModel model(LoadConfigFile(SourceDir() + "/config/huang2021.toml"));
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  for (int channel = 0; channel < kCueChannels; ++channel) {
    const auto& points = out["omct"][CueChannelName(channel)];
    ASSERT_EQ(points.size(), kOmctFrequencies_rad_s.size()) << CueChannelName(channel);
    const OmctPoint one = MeasureOmct(model, config, channel, kOmctFrequencies_rad_s[5], OmctAmplitude(channel));
    EXPECT_DOUBLE_EQ(points[5]["frequency_rad_s"].get<double>(), kOmctFrequencies_rad_s[5]);
    EXPECT_DOUBLE_EQ(points[5]["gain"].get<double>(), one.gain) << CueChannelName(channel);
    EXPECT_DOUBLE_EQ(points[5]["phase_deg"].get<double>(), one.phase_deg) << CueChannelName(channel);
  }
}

TEST(EdspCueingCli, BenchJsonHasEveryFigureOfEveryAlgorithmAndTheirRatio) {
  const auto run =
      RunCueing("bench" + kConfigs + " --manoeuvre " + SourceDir() +
                "/config/manoeuvres/braking.toml --cycles 3000 --seed 9 --variants 2 --variant-seed 5 --json");
  ASSERT_EQ(run.exit_code, 0) << run.text;
  const auto out = nlohmann::json::parse(run.text);
  const auto& washout = out["algorithms"]["classical_washout"];
  EXPECT_TRUE(washout["perception_error"]["braking"].is_number());
  EXPECT_DOUBLE_EQ(washout["perception_error"]["overall"].get<double>(),
                   washout["perception_error"]["braking"].get<double>());
  EXPECT_FALSE(washout.contains("perception_error_real"));  // no --rig-effects
  EXPECT_EQ(washout["soak"]["cycles"], 3000);
  EXPECT_EQ(washout["soak"]["seed"], 9);
  EXPECT_EQ(washout["limit_violations"], washout["soak"]["refused_setpoints"]);  // braking leaves none
  EXPECT_GT(washout["solve_ms"]["p99"].get<double>(), 0.0);
  const auto& mpc = out["algorithms"]["mpc"];
  EXPECT_EQ(mpc["soak"]["cycles"], 3000);
  EXPECT_EQ(mpc["limit_violations"], 0) << mpc["soak"]["first_refusal"];
  EXPECT_GT(mpc["solve_ms"]["p99"].get<double>(), mpc["solve_ms"]["p50"].get<double>() * 0.99);
  EXPECT_DOUBLE_EQ(mpc["solve_period_ms"].get<double>(), 10.0);
  EXPECT_EQ(out["ratio_of"], "perception_error");  // no --rig-effects: the commanded motion's
  EXPECT_DOUBLE_EQ(out["ratio"].get<double>(), mpc["perception_error"]["overall"].get<double>() /
                                                   washout["perception_error"]["overall"].get<double>());
  // The variants: the library's, scored as the offline runs score them.
  const PlatformModel model(LoadConfigFile(SourceDir() + "/config/huang2021.toml"));
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  double washout_sum = 0.0;
  for (const Manoeuvre& v : ManoeuvreVariants(LoadManoeuvre(SourceDir() + "/config/manoeuvres/braking.toml"), 2, 5)) {
    washout_sum += edsp::RunCueing(model, config, CueingAlgorithm::kClassicalWashout, v).score.overall;
  }
  EXPECT_NEAR(washout["perception_error_variants"]["overall"].get<double>(), washout_sum / 2, 1e-12);
  EXPECT_EQ(washout["perception_error_variants"]["seed"], 5);
  EXPECT_DOUBLE_EQ(out["ratio_variants"].get<double>(),
                   mpc["perception_error_variants"]["overall"].get<double>() /
                       washout["perception_error_variants"]["overall"].get<double>());
  EXPECT_TRUE(out["delay_p99_ms"].is_null());
  EXPECT_FALSE(out["delay_why_null"].get<std::string>().empty());
  EXPECT_EQ(out["omct"]["wz"].size(), kOmctFrequencies_rad_s.size());
}

TEST(EdspCueingCli, WritesOneCsvPerManoeuvre) {
  const std::string dir = test_support::ScratchDir("cueing_csv");
  const auto run = RunCueing("offline" + kConfigs + " --manoeuvre " + SourceDir() +
                             "/config/manoeuvres/braking.toml --csv-dir " + dir);
  ASSERT_EQ(run.exit_code, 0) << run.text;
  EXPECT_NE(run.text.find("braking"), std::string::npos) << run.text;
  std::ifstream csv(dir + "/braking.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t_s,vehicle_fx,", 0), 0u) << header;
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 10001);  // 10 s at 1 kHz, both ends
}

TEST(EdspCueingCli, ABadCueingConfigIsNamedWithANonZeroExit) {
  const std::string dir = test_support::ScratchDir("cueing_bad");
  const std::string path = dir + "/cueing.toml";
  std::ofstream(path) << "[washout]\ntilt_rate_max_rad_s = -1\n";
  const auto run = RunCueing("offline --config " + SourceDir() + "/config/huang2021.toml --cueing " + path +
                             " --manoeuvre " + SourceDir() + "/config/manoeuvres/braking.toml");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.text.find(path + ":2: [washout] tilt_rate_max_rad_s = -1 must be > 0"), std::string::npos) << run.text;
}

TEST(EdspCueingCli, ScoringALogOfNoCueingNamesTheLogAndWhatItLacks) {
  const std::string dir = test_support::ScratchDir("cueing_score");
  const std::string path = dir + "/empty.lcmlog";
  std::ofstream(path).flush();
  const auto run = RunCueing("score --log " + path + " --cueing " + SourceDir() + "/config/cueing.toml");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.text.find(path + ": no setpoint of a cueing"), std::string::npos) << run.text;
}

TEST(EdspCueingCli, SendRefusesTheBusOptionsWithAUdpAddressAndAnUnknownInput) {
  const auto send = RunCueing("send --manoeuvre " + SourceDir() + "/config/manoeuvres/braking.toml --session-id 3");
  EXPECT_NE(send.exit_code, 0);
  EXPECT_NE(send.text.find("give --to lcm, not --to 127.0.0.1:7400"), std::string::npos) << send.text;
  const auto live = RunCueing("live --cueing " + SourceDir() + "/config/cueing.toml --input can");
  EXPECT_NE(live.exit_code, 0);
  EXPECT_NE(live.text.find("--input"), std::string::npos) << live.text;
}

}  // namespace
}  // namespace edsp
