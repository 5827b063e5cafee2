#include "edsp/planner/paper_motions.h"

#include <random>
#include <stdexcept>

#include <fmt/format.h>

namespace edsp {

std::vector<std::string> PaperMotionNames() { return {"Lz", "Lx", "Rz", "Ry"}; }

namespace {

int AxisOf(const std::string& name) {
  static const char* kNames[] = {"Lx", "Ly", "Lz", "Rx", "Ry", "Rz"};
  for (int axis = 0; axis < 6; ++axis) {
    if (name == kNames[axis]) return axis;
  }
  throw std::invalid_argument(
      fmt::format("unknown motion \"{}\" (known: Lx Ly Lz Rx Ry Rz, M1…M999 mixed, calibration)", name));
}

// "M<k>" (k = 1…999): a mixed motion, every axis at once.
bool MixedIndex(const std::string& name, int* index) {
  if (name.size() < 2 || name.size() > 4 || name[0] != 'M') return false;
  for (std::size_t k = 1; k < name.size(); ++k) {
    if (name[k] < '0' || name[k] > '9') return false;
  }
  *index = std::stoi(name.substr(1));
  return *index >= 1;
}

// Stop k of mixed motion `index`: each axis at a deterministic draw within
// kMixedShare of its range, so the combination stays inside the workspace.
Vector6 MixedStop(const Vector6& home, const PaperMotionOptions& o, int index, int stop) {
  constexpr double kMixedShare = 0.35;
  std::mt19937_64 rng(static_cast<std::uint64_t>(index) * 7919u + static_cast<std::uint64_t>(stop));
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Vector6 target = home;
  for (int axis = 0; axis < 6; ++axis) {
    target(axis) += kMixedShare * (axis < 3 ? o.linear_range_m : o.angular_range_rad) * unit(rng);
  }
  return target;
}

}  // namespace

void AppendPaperMotion(const std::string& name, const Vector6& home, const PaperMotionOptions& o,
                       TrajectorySequence* sequence) {
  int mixed = 0;
  const bool is_mixed = MixedIndex(name, &mixed);
  const int axis = is_mixed ? -1 : AxisOf(name);
  if (o.stops < 2) throw std::invalid_argument("paper motion needs at least 2 stops");
  const double range = axis < 3 ? o.linear_range_m : o.angular_range_rad;  // of a single axis
  Vector6 at = sequence->size() == 0 ? home : sequence->EndPose();
  auto move_to = [&](const Vector6& target, const std::string& label) {
    if ((target - at).cwiseAbs().maxCoeff() > 0.0) {
      // All six axes at once add up in the legs: half of each axis's speed.
      const double share = is_mixed ? 0.5 : 1.0;
      sequence->Append(fmt::format("{}/move {}", name, label),
                       std::make_unique<QuinticMove>(
                           QuinticMove::WithinLimits(at, target, share * o.max_speed_m_s, share * o.max_speed_rad_s)));
    }
    sequence->Append(fmt::format("{}/dwell {}", name, label), std::make_unique<Dwell>(target, o.dwell_s));
    at = target;
  };
  for (int k = 0; k < o.stops; ++k) {
    Vector6 target = home;
    if (is_mixed) {
      target = MixedStop(home, o, mixed, k);
    } else {
      target(axis) += range * (-1.0 + 2.0 * k / (o.stops - 1));
    }
    move_to(target, std::to_string(k + 1));
  }
  move_to(home, "home");
}

std::vector<std::string> MotionNames(const std::string& list) {
  std::vector<std::string> names;
  std::string name;
  for (char c : list + ",") {
    if (c != ',') {
      name += c;
    } else if (!name.empty()) {
      names.push_back(name);
      name.clear();
    }
  }
  return names;
}

std::unique_ptr<TrajectorySequence> PaperMotionSequence(const std::vector<std::string>& names, const Vector6& home,
                                                        const PaperMotionOptions& options) {
  auto sequence = std::make_unique<TrajectorySequence>();
  for (const std::string& name : names) AppendPaperMotion(name, home, options, sequence.get());
  return sequence;
}

}  // namespace edsp
