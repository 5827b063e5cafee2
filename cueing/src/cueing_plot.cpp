#include "edsp/cueing/cueing_plot.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/cueing/vehicle_motion.h"

namespace edsp {
namespace {

constexpr double kPlotRate_hz = 100.0;  // what a figure resolves; the data stay small
// Panels row by row: each specific force beside the angular velocity of its tilt.
constexpr int kPanelChannels[kCueChannels] = {0, 4, 1, 3, 2, 5};
constexpr const char* kUnits[kCueChannels] = {"m/s²", "m/s²", "m/s²", "rad/s", "rad/s", "rad/s"};

void WriteData(const CueingRun& run, const VestibularParameters& perception, const std::string& path) {
  const auto vehicle = Perceive(perception, run.vehicle);
  const auto platform = Perceive(perception, run.platform);
  const auto every = static_cast<std::size_t>(std::max(1.0, 1.0 / (kPlotRate_hz * run.vehicle.period_s)));
  std::ofstream out(path);
  out << "# t_s, perceived in the vehicle fx fy fz-g wx wy wz, on the platform fx fy fz-g wx wy wz\n";
  for (std::size_t k = 0; k < run.vehicle.samples.size(); k += every) {
    out << fmt::format("{:.3f}", run.vehicle.samples[k].t_s);
    for (const auto* felt : {&vehicle, &platform}) {
      for (int channel = 0; channel < kCueChannels; ++channel) {
        const double offset = channel == 2 ? kStandardGravity_m_s2 : 0.0;
        out << fmt::format(" {:.6g}", (*felt)[static_cast<std::size_t>(channel)][k] - offset);
      }
    }
    out << "\n";
  }
  if (!out.flush()) throw std::runtime_error(path + ": cannot write");
}

std::string Script(const CueingRun& run, const std::string& algorithm, const std::string& name, const std::string& dat,
                   const std::string& png) {
  std::string gp = fmt::format(
      "set terminal pngcairo size 1000,760 font ',10'\nset output '{}'\nset grid\nset key top right\n"
      "set multiplot layout 3,2 title '{}: perceived in the vehicle and on the platform ({}), error {:.2f} "
      "thresholds'\n",
      png, name, algorithm, run.score.overall);
  for (int channel : kPanelChannels) {
    const ChannelScore& s = run.score.channels[static_cast<std::size_t>(channel)];
    gp += fmt::format(
        "set title '{}{}: error {:.2f} thresholds, correlation {:.2f}'\nset ylabel '{}'\n"
        "plot '{}' using 1:{} with lines lw 2 lc rgb 'black' title 'vehicle', "
        "'' using 1:{} with lines lw 2 lc rgb '#1f77b4' title 'platform'\n",
        CueChannelName(channel), channel == 2 ? " − g" : "", s.in_thresholds, s.correlation, kUnits[channel], dat,
        2 + channel, 2 + kCueChannels + channel);
  }
  return gp + "unset multiplot\n";
}

}  // namespace

std::string PlotCueingRun(const CueingRun& run, const VestibularParameters& perception, const std::string& algorithm,
                          const std::string& dir, const std::string& name) {
  const std::string stem = (std::filesystem::path(dir) / name).string();
  const std::string dat = stem + ".dat", script = stem + ".gp", png = stem + ".png";
  WriteData(run, perception, dat);
  std::ofstream gp(script);
  gp << Script(run, algorithm, name, dat, png);
  if (!gp.flush()) throw std::runtime_error(script + ": cannot write");
  std::filesystem::remove(png);  // a figure left from an earlier run is not this one
  const int rc = std::system(fmt::format("gnuplot '{}' 2>'{}.err'", script, stem).c_str());
  if (rc != 0 || !std::filesystem::exists(png)) {
    throw std::runtime_error(
        fmt::format("gnuplot {} failed (exit {}; see {}.err). Is gnuplot-nox installed? deploy/edsp deps installs it",
                    script, rc, stem));
  }
  std::filesystem::remove(stem + ".err");
  return png;
}

}  // namespace edsp
