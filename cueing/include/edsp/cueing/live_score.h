#pragma once
// A live run's cueing scored from what its log holds: what the rider
// should have felt (the vehicle's samples as the cueing heard them) against
// what the platform made them feel, commanded (the planner's setpoints
// while cueing) and real (the rig's truth; on a real rig, the pose from
// the encoders). Each stream is put on one grid at the stack's 1 kHz by its
// own stamps: a vehicle sample is held until the next one came (as the
// cueing holds it), the poses followed by a smooth curve through them (a
// real rig's encoder pose comes at 100 Hz); the grid
// spans the longest time the planner followed the cueing while the
// vehicle was heard without a silence the cueing took for a lost input
// (what the vehicle did then is not known). So the real score carries the whole chain's lag and the drives'
// tracking: the cueing's own sim-to-real gap, on the live rig.

#include <cstdint>
#include <optional>
#include <vector>

#include "edsp/cueing/cueing_config.h"
#include "edsp/cueing/perception_score.h"
#include "edsp/kinematics/types.h"

namespace edsp {

struct HeardVehicleSample {
  std::int64_t utime = 0;  // when it was heard (the log's receipt)
  Vector3 specific_force_m_s2 = Vector3::Zero();
  Vector3 angular_velocity_rad_s = Vector3::Zero();
};

struct StampedPose {
  std::int64_t utime = 0;  // the instant the pose is of
  Vector6 pose = Vector6::Zero();
};

struct LiveCueingScore {
  std::int64_t start_utime = 0;
  double duration_s = 0.0;
  std::size_t grid_samples = 0;
  PerceptionScore commanded;
  std::optional<PerceptionScore> real;  // when real poses span the grid
};

inline constexpr double kLiveScorePeriod_s = 1e-3;

// Each stream in time order; `commanded` one stretch of cueing. Throws
// std::invalid_argument naming what is missing: no vehicle sample or
// commanded pose, or less than 10 ms where both are (a log of no cueing,
// or of another run).
LiveCueingScore ScoreLiveCueing(const CueingConfig& config, const std::vector<HeardVehicleSample>& vehicle,
                                const std::vector<StampedPose>& commanded, const std::vector<StampedPose>& real);

}  // namespace edsp
