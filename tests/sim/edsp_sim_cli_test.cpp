// edsp-sim as a user runs it: JSON outputs match the library, bad input gets
// a non-zero exit and a message naming what is wrong.
#include <unistd.h>

#include <array>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "edsp/kinematics/config.h"
#include "edsp/sim/paper_table.h"
#include "command_output.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

using CommandRun = test_support::CommandOutput;

CommandRun RunSim(const std::string& arguments) {
  return test_support::RunCommand(BuiltProgram("edsp-sim") + " " + arguments);
}

const std::string kConfig = std::string("--config ") + SourceDir() + "/config/huang2021.toml";

TEST(EdspSimCli, PrJsonMatchesTheLibrary) {
  const CommandRun run = RunSim("pr " + kConfig + " --pose=0.1,-0.05,1.6,0.05,-0.1,0.2 --json");
  ASSERT_EQ(run.exit_code, 0) << run.text;
  const auto out = nlohmann::json::parse(run.text);
  const PlatformModel model(Huang2021Config());
  Pose pose;
  pose.p_BoMo_B << 0.1, -0.05, 1.6;
  pose.rpy_rad << 0.05, -0.1, 0.2;
  const LegSolution legs = model.Solve(pose);
  const Vector6 pr = model.PrLengthError(legs, PrMode::kSigned);
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_DOUBLE_EQ(out["length_m"][i].get<double>(), legs.length_m(i));
    EXPECT_DOUBLE_EQ(out["twist_rad"][i].get<double>(), legs.twist_rad(i));
    EXPECT_DOUBLE_EQ(out["pr_correction_m"][i].get<double>(), pr(i));
  }
}

TEST(EdspSimCli, PaperTableJsonHasEveryMotionAndMode) {
  const CommandRun run = RunSim("paper-table " + kConfig + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.text;
  const auto out = nlohmann::json::parse(run.text);
  for (const char* motion : {"Lz", "Lx", "Rz", "Ry"}) {
    for (const char* key : {"none_max_m", "unsigned_max_m", "signed_max_m", "asin_max_m"}) {
      ASSERT_TRUE(out["motions"][motion][key].is_number()) << motion << " " << key;
    }
    EXPECT_LT(out["motions"][motion]["signed_max_m"].get<double>(), 1e-9);
    EXPECT_GT(out["motions"][motion]["none_max_m"].get<double>(), 1e-4);
  }
}

TEST(EdspSimCli, PaperTableTextLooksLikeTable1) {
  const CommandRun run = RunSim("paper-table " + kConfig);
  ASSERT_EQ(run.exit_code, 0) << run.text;
  for (const char* part : {"Lz", "Lx", "Rz", "Ry", "unsigned Eq.(9)", "signed (edsp)"}) {
    EXPECT_NE(run.text.find(part), std::string::npos) << part;
  }
}

void ExpectFailure(const std::string& arguments, const std::string& fragment) {
  const CommandRun run = RunSim(arguments);
  EXPECT_NE(run.exit_code, 0) << arguments;
  EXPECT_NE(run.text.find(fragment), std::string::npos) << arguments << "\nprinted: " << run.text;
}

TEST(EdspSimCli, BadInputFailsWithAMessageNamingIt) {
  ExpectFailure("pr " + kConfig + " --pose=0,0,1.5,nan,0,0", "roll");
  ExpectFailure("pr " + kConfig + " --pose=0,0,1.5,0,0", "exactly six");
  ExpectFailure("pr " + kConfig + " --pose=0,0,2.4,0,0,0", "leg_max_m");
  ExpectFailure("pr --config /nonexistent.toml --pose=0,0,1.5,0,0,0", "/nonexistent.toml");
  ExpectFailure("pr --pose=0,0,1.5,0,0,0", "--config");
  ExpectFailure("paper-table " + kConfig + " --poses 1", "--poses");
  ExpectFailure("", "subcommand");
}

TEST(EdspSimCli, ConfigErrorNamesTheKey) {
  char path[] = "/tmp/edsp_cli_test_XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  const std::string text = "[geometry]\npreset = \"huang2021\"\n[drive]\nlead_m = -0.01\n";
  ASSERT_EQ(write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size()));
  close(fd);
  ExpectFailure(std::string("paper-table --config ") + path, "[drive] lead_m = -0.01");
  unlink(path);
}

}  // namespace
}  // namespace edsp
