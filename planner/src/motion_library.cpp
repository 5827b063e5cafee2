#include "edsp/planner/motion_library.h"

#include <memory>

#include "edsp/planner/csv_trajectory.h"

namespace edsp {

void AppendMotion(const PlatformModel& model, const std::string& name, const PaperMotionOptions& paper,
                  TrajectorySequence* sequence, const CalibrationMotionOptions& calibration) {
  if (name == "calibration") {
    AppendCalibrationMotions(model, paper, calibration, sequence);
  } else {
    AppendPaperMotion(name, model.home_pose().ToVector(), paper, sequence);
  }
}

std::unique_ptr<TrajectorySequence> MotionSequence(const PlatformModel& model, const std::vector<std::string>& names,
                                                   const PaperMotionOptions& paper,
                                                   const CalibrationMotionOptions& calibration) {
  auto sequence = std::make_unique<TrajectorySequence>();
  for (const std::string& name : names) AppendMotion(model, name, paper, sequence.get(), calibration);
  return sequence;
}

std::unique_ptr<TrajectorySequence> PlannedTrajectory(const PlatformModel& model, const std::string& motions,
                                                      const std::string& csv_path, const PaperMotionOptions& paper) {
  if (csv_path.empty()) return MotionSequence(model, MotionNames(motions), paper);
  auto sequence = std::make_unique<TrajectorySequence>();
  auto file = std::make_unique<CsvTrajectory>(CsvTrajectory::Load(csv_path));
  const Vector6 start = file->Sample(0.0).pose;
  const Vector6 home = model.home_pose().ToVector();
  if ((start - home).cwiseAbs().maxCoeff() > 1e-9) {
    sequence->Append("approach", std::make_unique<QuinticMove>(QuinticMove::WithinLimits(
                                     home, start, paper.max_speed_m_s, paper.max_speed_rad_s)));
  }
  sequence->Append(csv_path, std::move(file));
  return sequence;
}

}  // namespace edsp
