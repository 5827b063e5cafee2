#include "edsp/sim/stack_report.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/sim/paper_table.h"

namespace edsp {

namespace {

std::vector<std::string> MotionsInOrder(const std::vector<DwellError>& dwells) {
  std::vector<std::string> motions;
  for (const DwellError& d : dwells) {
    if (std::find(motions.begin(), motions.end(), d.motion) == motions.end()) motions.push_back(d.motion);
  }
  return motions;
}

std::set<PrMode> Modes(const std::vector<DwellError>& dwells) {
  std::set<PrMode> modes;
  for (const DwellError& d : dwells) modes.insert(d.pr_mode);
  return modes;
}

bool IsAngular(const std::string& motion) { return !motion.empty() && motion[0] == 'R'; }

// Displacement in the unit the paper plots: mm or degrees.
double PlotDisplacement(const DwellError& d) {
  return IsAngular(d.motion) ? d.displacement * 180.0 / kPi : d.displacement * 1e3;
}

}  // namespace

std::vector<StackTableRow> StackTable(const std::vector<DwellError>& dwells, const PlatformModel& model) {
  std::vector<StackTableRow> rows;
  for (const std::string& motion : MotionsInOrder(dwells)) {
    for (PrMode mode : Modes(dwells)) {
      StackTableRow row;
      row.motion = motion;
      row.mode = mode;
      double sum_sq = 0.0;
      for (const DwellError& d : dwells) {
        if (d.motion != motion || d.pr_mode != mode) continue;
        ++row.stops;
        row.max_measured_m = std::max(row.max_measured_m, d.error_norm_m());
        sum_sq += d.error_m.squaredNorm();
        row.max_predicted_m = std::max(row.max_predicted_m, PointAError(model, Pose::FromVector(d.target), mode));
      }
      if (row.stops == 0) continue;
      row.rms_measured_m = std::sqrt(sum_sq / row.stops);
      rows.push_back(row);
    }
  }
  return rows;
}

std::string FormatStackTable(const std::vector<StackTableRow>& rows) {
  std::vector<PrMode> modes;
  std::vector<std::string> motions;
  for (const StackTableRow& r : rows) {
    if (std::find(modes.begin(), modes.end(), r.mode) == modes.end()) modes.push_back(r.mode);
    if (std::find(motions.begin(), motions.end(), r.motion) == motions.end()) motions.push_back(r.motion);
  }
  std::sort(modes.begin(), modes.end());
  std::string out = fmt::format("{:<8}", "motion");
  for (PrMode m : modes) out += fmt::format(" {:>22}", std::string(PrModeName(m)) + " mm (model)");
  out += "\n";
  for (const std::string& motion : motions) {
    out += fmt::format("{:<8}", motion);
    for (PrMode m : modes) {
      const auto it = std::find_if(rows.begin(), rows.end(),
                                   [&](const StackTableRow& r) { return r.motion == motion && r.mode == m; });
      out += it == rows.end()
                 ? fmt::format(" {:>22}", "-")
                 : fmt::format(" {:>13.4f} ({:>6.4f})", it->max_measured_m * 1e3, it->max_predicted_m * 1e3);
    }
    out += "\n";
  }
  return out;
}

std::vector<std::string> WriteStackPlots(const std::vector<DwellError>& dwells, const PlatformModel& model,
                                         const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create directory (" + ec.message() + ")");
  std::vector<std::string> pngs;
  for (const std::string& motion : MotionsInOrder(dwells)) {
    const std::string stem = (std::filesystem::path(dir) / motion).string();
    std::string plot_cmd;
    for (PrMode mode : Modes(dwells)) {
      const std::string dat = fmt::format("{}_{}.dat", stem, PrModeName(mode));
      std::ofstream out(dat);
      out << "# displacement (" << (IsAngular(motion) ? "deg" : "mm")
          << ")  measured_error_mm  predicted_error_mm  error_x_mm error_y_mm error_z_mm\n";
      std::vector<const DwellError*> points;
      for (const DwellError& d : dwells) {
        if (d.motion == motion && d.pr_mode == mode) points.push_back(&d);
      }
      std::sort(points.begin(), points.end(),
                [](const DwellError* a, const DwellError* b) { return a->displacement < b->displacement; });
      for (const DwellError* d : points) {
        out << fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f}\n", PlotDisplacement(*d), d->error_norm_m() * 1e3,
                           PointAError(model, Pose::FromVector(d->target), mode) * 1e3, d->error_m.x() * 1e3,
                           d->error_m.y() * 1e3, d->error_m.z() * 1e3);
      }
      if (!out) throw std::runtime_error(dat + ": cannot write");
      if (points.empty()) continue;
      const int colour = static_cast<int>(mode) + 1;
      plot_cmd += fmt::format(
          "{}'{}' using 1:2 with linespoints lw 2 pt 7 lc {} title '{} (tracker)', "
          "'{}' using 1:3 with lines dt 2 lc {} title '{} (model)'",
          plot_cmd.empty() ? "" : ", ", dat, colour, PrModeName(mode), dat, colour, PrModeName(mode));
    }
    const std::string png = stem + ".png";
    const std::string script = stem + ".gp";
    std::ofstream gp(script);
    gp << "set terminal pngcairo size 900,560 font ',11'\n"
       << "set output '" << png << "'\n"
       << "set title 'Motion " << motion << ": point-A error at each stop, by PR compensation'\n"
       << "set xlabel '" << (IsAngular(motion) ? "rotation (deg)" : "displacement (mm)") << "'\n"
       << "set ylabel 'point-A error (mm)'\nset grid\nset key top left\n"
       << "plot " << plot_cmd << "\n";
    gp.close();
    if (!gp) throw std::runtime_error(script + ": cannot write");
    const int rc = std::system(fmt::format("gnuplot '{}' 2>'{}.err'", script, stem).c_str());
    if (rc != 0) {
      throw std::runtime_error(
          fmt::format("gnuplot {} failed (exit {}; see {}.err). Is gnuplot-nox installed? deploy/edsp deps "
                      "installs it",
                      script, rc, stem));
    }
    std::filesystem::remove(stem + ".err", ec);
    pngs.push_back(png);
  }
  return pngs;
}

}  // namespace edsp
