// A manoeuvre's figure: its data are the perceived channels of the run
// (one row per 10 ms, fz less g), its script draws all six, gnuplot makes
// a PNG of it, and a directory it cannot write to is named.
#include "edsp/cueing/cueing_plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/manoeuvre.h"
#include "edsp/kinematics/config.h"
#include "edsp/node/build_paths.h"
#include "scratch_dir.h"

namespace edsp {
namespace {

std::vector<std::vector<double>> ReadRows(const std::string& path) {
  std::vector<std::vector<double>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    rows.emplace_back();
    for (double v; fields >> v;) rows.back().push_back(v);
  }
  return rows;
}

TEST(CueingPlot, TheFigureDrawsThePerceivedChannelsOfTheRun) {
  const PlatformModel model(LoadConfigFile(SourceDir() + "/config/huang2021.toml"));
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  const Manoeuvre braking = LoadManoeuvre(SourceDir() + "/config/manoeuvres/braking.toml");
  const CueingRun run = RunCueing(model, config, CueingAlgorithm::kClassicalWashout, braking);
  const std::string dir = test_support::ScratchDir("cueing_plot");
  const std::string png = PlotCueingRun(run, config.perception, "classical_washout", dir, "braking");

  std::ifstream image(png, std::ios::binary);
  char magic[4] = {};
  image.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG") << png;

  const auto rows = ReadRows(dir + "/braking.dat");
  const double duration_s = run.vehicle.samples.back().t_s - run.vehicle.samples.front().t_s;
  EXPECT_NEAR(static_cast<double>(rows.size()), duration_s * 100.0 + 1.0, 2.0);
  const auto vehicle = Perceive(config.perception, run.vehicle);
  const auto platform = Perceive(config.perception, run.platform);
  const std::size_t every = 10;  // 1 kHz to the figure's 100 Hz
  for (std::size_t r = 0; r < rows.size(); r += 37) {
    ASSERT_EQ(rows[r].size(), 13U);
    const std::size_t k = r * every;
    EXPECT_NEAR(rows[r][0], run.vehicle.samples[k].t_s, 1e-3);
    EXPECT_NEAR(rows[r][1], vehicle[0][k], 1e-5 * (1.0 + std::fabs(vehicle[0][k])));     // fx
    EXPECT_NEAR(rows[r][3], vehicle[2][k] - kStandardGravity_m_s2, 1e-5);                // fz − g
    EXPECT_NEAR(rows[r][7], platform[0][k], 1e-5 * (1.0 + std::fabs(platform[0][k])));   // fx
    EXPECT_NEAR(rows[r][11], platform[4][k], 1e-5 * (1.0 + std::fabs(platform[4][k])));  // wy
  }
  EXPECT_NEAR(rows.front()[3], 0.0, 1e-6) << "a rider at rest feels g, drawn as zero";

  std::ostringstream script;
  script << std::ifstream(dir + "/braking.gp").rdbuf();
  const std::string text = script.str();
  for (const char* channel : {"fx", "fy", "fz", "wx", "wy", "wz"}) {
    EXPECT_NE(text.find(std::string("set title '") + channel), std::string::npos) << channel;
  }
}

TEST(CueingPlot, ADirectoryItCannotWriteToIsNamed) {
  const PlatformModel model(LoadConfigFile(SourceDir() + "/config/huang2021.toml"));
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  const CueingRun run = RunCueing(model, config, CueingAlgorithm::kClassicalWashout,
                                  LoadManoeuvre(SourceDir() + "/config/manoeuvres/braking.toml"));
  try {
    PlotCueingRun(run, config.perception, "classical_washout", "/nonexistent/edsp", "braking");
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/edsp/braking.dat"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edsp
