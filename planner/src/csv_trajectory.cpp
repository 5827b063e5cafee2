#include "edsp/planner/csv_trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace edsp {

namespace {

std::vector<std::string> SplitRow(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char c : line) {
    if (c == ',') {
      cells.emplace_back();
    } else if (c != '\r' && c != ' ' && c != '\t') {
      cells.back() += c;
    }
  }
  return cells;
}

}  // namespace

CsvTrajectory CsvTrajectory::Parse(const std::string& text, const std::string& origin) {
  static const char* kColumns[] = {"time_s", "x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"};
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  int index[7] = {-1, -1, -1, -1, -1, -1, -1};
  bool header = false;
  CsvTrajectory trajectory;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> cells = SplitRow(line);
    if (!header) {
      for (std::size_t c = 0; c < cells.size(); ++c) {
        for (int k = 0; k < 7; ++k) {
          if (cells[c] == kColumns[k]) index[k] = static_cast<int>(c);
        }
      }
      for (int k = 0; k < 7; ++k) {
        if (index[k] < 0) {
          throw std::runtime_error(fmt::format("{}:{}: header lacks column {}", origin, line_number, kColumns[k]));
        }
      }
      header = true;
      continue;
    }
    double values[7];
    for (int k = 0; k < 7; ++k) {
      const std::size_t c = static_cast<std::size_t>(index[k]);
      const std::string cell = c < cells.size() ? cells[c] : "";
      char* end = nullptr;
      values[k] = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || !std::isfinite(values[k])) {
        throw std::runtime_error(
            fmt::format("{}:{}:{}: {} = \"{}\" is not a finite number", origin, line_number, c + 1, kColumns[k], cell));
      }
    }
    if (!trajectory.times_.empty() && !(values[0] > trajectory.times_.back())) {
      throw std::runtime_error(
          fmt::format("{}:{}:{}: time_s = {} does not increase", origin, line_number, index[0] + 1, values[0]));
    }
    trajectory.times_.push_back(values[0]);
    Vector6 pose;
    for (int k = 0; k < 6; ++k) pose(k) = values[k + 1];
    trajectory.poses_.push_back(pose);
  }
  if (trajectory.times_.size() < 2) {
    throw std::runtime_error(fmt::format("{}: needs a header and at least two rows", origin));
  }
  return trajectory;
}

CsvTrajectory CsvTrajectory::Load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open trajectory file", path));
  std::ostringstream text;
  text << in.rdbuf();
  return Parse(text.str(), path);
}

PoseSample CsvTrajectory::Sample(double t_s) const {
  const double t = std::clamp(times_.front() + t_s, times_.front(), times_.back());
  const auto it = std::upper_bound(times_.begin(), times_.end(), t);
  const std::size_t hi = std::min<std::size_t>(static_cast<std::size_t>(it - times_.begin()), times_.size() - 1);
  const std::size_t lo = hi - 1;
  const double span = times_[hi] - times_[lo];
  const double a = (t - times_[lo]) / span;
  PoseSample sample;
  sample.pose = (1.0 - a) * poses_[lo] + a * poses_[hi];
  if (t_s >= 0.0 && t_s < duration_s()) sample.velocity = (poses_[hi] - poses_[lo]) / span;
  return sample;
}

}  // namespace edsp
