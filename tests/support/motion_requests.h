#pragma once
// Motion requests as a client builds them (edsp-ctl's fields), for tests of
// the planner's motion service.
#include <cstdint>
#include <string>

#include "edsp/kinematics/types.h"
#include "edsp/motion_request_t.hpp"

namespace edsp::test_support {

class MotionRequests {
 public:
  explicit MotionRequests(std::int64_t session_id) : session_id_(session_id) {}

  motion_request_t Make(std::int8_t kind, std::int64_t now_utime) {
    motion_request_t r{};
    r.utime = now_utime;
    r.seq = ++seq_;
    r.session_id = session_id_;
    r.request_id = ++id_;
    r.client = "test";
    r.kind = kind;
    return r;
  }
  motion_request_t Move(const Vector6& pose, std::int64_t now_utime, bool relative = false,
                        const std::string& frame = "") {
    motion_request_t r = Make(motion_request_t::KIND_MOVE, now_utime);
    for (int k = 0; k < 6; ++k) r.pose[k] = pose(k);
    r.relative = relative;
    r.frame = frame;
    return r;
  }
  motion_request_t Frame(const std::string& name, const Vector6& pose, std::int64_t now_utime) {
    motion_request_t r = Make(motion_request_t::KIND_FRAME, now_utime);
    r.frame = name;
    for (int k = 0; k < 6; ++k) r.pose[k] = pose(k);
    return r;
  }
  // A cueing source's engage (to `neutral`) or disengage (to `pose`).
  motion_request_t Engage(const Vector6& neutral, std::int64_t now_utime, const std::string& source) {
    motion_request_t r = Move(neutral, now_utime);
    r.kind = motion_request_t::KIND_ENGAGE;
    r.client = source;
    return r;
  }
  motion_request_t Disengage(const Vector6& pose, std::int64_t now_utime) {
    motion_request_t r = Move(pose, now_utime);
    r.kind = motion_request_t::KIND_DISENGAGE;
    return r;
  }
  // A jog by `step` along pose axis `axis` (0..5: x, y, z, roll, pitch, yaw) of `frame`.
  motion_request_t Jog(int axis, double step, std::int64_t now_utime, const std::string& frame = "") {
    motion_request_t r = Make(motion_request_t::KIND_JOG, now_utime);
    r.pose[axis] = step;
    r.frame = frame;
    return r;
  }
  motion_request_t Pivot(const Vector3& c, std::int64_t now_utime) {
    motion_request_t r = Make(motion_request_t::KIND_PIVOT, now_utime);
    for (int k = 0; k < 3; ++k) r.point[k] = c(k);
    return r;
  }

 private:
  std::int64_t session_id_;
  std::int64_t seq_ = 0, id_ = 0;
};

}  // namespace edsp::test_support
