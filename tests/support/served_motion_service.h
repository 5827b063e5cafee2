#pragma once
// The planner's motion service alone, cycled by hand on its own clock with
// a bridge whose drives follow (or hold): for tests of what it serves.
#include <cstdint>

#include <Eigen/Core>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/leg_state_t.hpp"
#include "edsp/planner/motion_service.h"
#include "edsp/pose_setpoint_t.hpp"
#include "motion_requests.h"

namespace edsp::test_support {

inline constexpr std::int64_t kServiceSession = 7;
inline constexpr std::int64_t kServiceT0 = 1'700'000'000'000'000;

inline Vector6 Vec(double x, double y, double z, double roll = 0, double pitch = 0, double yaw = 0) {
  Vector6 v;
  v << x, y, z, roll, pitch, yaw;
  return v;
}

class Served {
 public:
  explicit Served(const PlatformConfig& config = Huang2021Config())
      : model_(config), service_(model_, Options()), requests_(kServiceSession) {
    Cycle();
  }

  static MotionServiceOptions Options() {
    MotionServiceOptions o;
    o.session_id = kServiceSession;
    return o;
  }
  // One planner cycle with a bridge whose drives all follow (or hold).
  pose_setpoint_t Cycle(std::int8_t drives = leg_state_t::DRIVE_ENABLED) {
    leg_state_t legs{};
    for (auto& d : legs.drive_status) d = drives;
    service_.OnLegState(legs, now_);
    const pose_setpoint_t sp = service_.Step(now_);
    now_ += 1000;
    return sp;
  }
  motion_reply_t Ask(motion_request_t r) { return service_.Handle(r, now_); }
  Vector6 Held() {
    const pose_setpoint_t sp = Cycle();
    return Eigen::Map<const Vector6>(sp.pose);
  }

  PlatformModel model_;
  MotionService service_;
  MotionRequests requests_;
  std::int64_t now_ = kServiceT0;
};

}  // namespace edsp::test_support
