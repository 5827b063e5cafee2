#include "edsp/planner/motion_library.h"

#include <memory>

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

}  // namespace edsp
