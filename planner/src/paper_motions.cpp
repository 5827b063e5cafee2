#include "edsp/planner/paper_motions.h"

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
      fmt::format("unknown motion \"{}\" (known: Lx Ly Lz Rx Ry Rz)", name));
}

}  // namespace

void AppendPaperMotion(const std::string& name, const Vector6& home,
                       const PaperMotionOptions& o, TrajectorySequence* sequence) {
  const int axis = AxisOf(name);
  if (o.stops < 2) throw std::invalid_argument("paper motion needs at least 2 stops");
  const double range = axis < 3 ? o.linear_range_m : o.angular_range_rad;
  Vector6 at = sequence->size() == 0 ? home : sequence->EndPose();
  auto move_to = [&](const Vector6& target, const std::string& label) {
    if ((target - at).cwiseAbs().maxCoeff() > 0.0) {
      sequence->Append(fmt::format("{}/move {}", name, label),
                       std::make_unique<QuinticMove>(QuinticMove::WithinLimits(
                           at, target, o.max_speed_m_s, o.max_speed_rad_s)));
    }
    sequence->Append(fmt::format("{}/dwell {}", name, label),
                     std::make_unique<Dwell>(target, o.dwell_s));
    at = target;
  };
  for (int k = 0; k < o.stops; ++k) {
    Vector6 target = home;
    target(axis) += range * (-1.0 + 2.0 * k / (o.stops - 1));
    move_to(target, std::to_string(k + 1));
  }
  move_to(home, "home");
}

}  // namespace edsp
