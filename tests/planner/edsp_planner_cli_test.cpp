// edsp-planner's offline report as a user runs it: the identifiability JSON
// is what the library computes for the same motions, and bad input (an
// unknown motion, a motion set the planner would refuse, --json alone) gets
// a non-zero exit and a message naming what is wrong.
#include <cstdio>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_output.h"
#include "edsp/kinematics/config.h"
#include "edsp/planner/identifiability.h"
#include "edsp/planner/motion_library.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

const std::string kConfig = std::string(" --config ") + SourceDir() + "/config/huang2021.toml";

test_support::CommandOutput Planner(const std::string& arguments) {
  return test_support::RunCommand(BuiltProgram("edsp-planner") + kConfig + " " + arguments);
}

TEST(EdspPlannerCli, IdentifiabilityJsonIsTheLibrarysForTheSameMotions) {
  const auto run = Planner("--motions calibration --identifiability --json");
  ASSERT_EQ(run.exit_code, 0) << run.text;
  const nlohmann::json j = nlohmann::json::parse(run.text);
  EXPECT_EQ(j.at("rate_hz").get<double>(), 100.0);
  EXPECT_EQ(j.at("noise_sigma_m").get<double>(), 5e-6);
  const PlatformModel model(Huang2021Config());
  const auto motions = MotionSequence(model, {"calibration"}, PaperMotionOptions{});
  const auto paper = MotionSequence(model, PaperMotionNames(), PaperMotionOptions{});
  EXPECT_NEAR(j.at("motions").at("duration_s").get<double>(), motions->duration_s(), 1e-9);
  EXPECT_NEAR(j.at("paper").at("duration_s").get<double>(), paper->duration_s(), 1e-9);
  const std::vector<Identifiability> expected = AssessIdentifiability(model, *motions, IdentifiabilityOptions{});
  const nlohmann::json& rows = j.at("motions").at("effects");
  ASSERT_EQ(rows.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(rows[k].at("effects").get<std::string>(), expected[k].effects);
    EXPECT_EQ(rows[k].at("parameters").get<int>(), expected[k].parameters);
    EXPECT_EQ(rows[k].at("samples").get<int>(), expected[k].samples);
    for (const char* key : {"condition", "o1", "o3"}) {
      const double want = key[0] == 'c' ? expected[k].condition : key[1] == '1' ? expected[k].o1 : expected[k].o3;
      EXPECT_NEAR(rows[k].at(key).get<double>(), want, 1e-9 * want) << expected[k].effects << " " << key;
    }
  }
  EXPECT_EQ(j.at("paper").at("effects").size(), expected.size());
}

TEST(EdspPlannerCli, AnUnknownMotionIsNamedWithTheKnownOnes) {
  const auto run = Planner("--motions Lz,Lw --identifiability");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.text.find("\"Lw\""), std::string::npos) << run.text;
  EXPECT_NE(run.text.find("calibration"), std::string::npos) << run.text;
}

TEST(EdspPlannerCli, MotionsOutsideTheWorkspaceAreRefusedNotJudged) {
  const std::string csv = testing::TempDir() + "/edsp_planner_cli_too_high.csv";
  {
    const Vector6 home = PlatformModel(Huang2021Config()).home_pose().ToVector();
    std::ofstream out(csv);
    out << "time_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad\n";
    for (int k = 0; k <= 100; ++k) {
      out << 0.1 * k << ",0,0," << home(2) + 0.02 * k << ",0,0,0\n";  // 2 m up: past the legs' stroke
    }
  }
  const auto run = Planner("--csv " + csv + " --identifiability");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.text.find("leaves the workspace"), std::string::npos) << run.text;
  std::remove(csv.c_str());
}

TEST(EdspPlannerCli, JsonWithoutTheReportItBelongsToIsAnError) {
  const auto run = Planner("--motions Lz --json");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.text.find("--identifiability"), std::string::npos) << run.text;
}

}  // namespace
}  // namespace edsp
