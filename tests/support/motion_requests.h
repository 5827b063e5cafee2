#pragma once
// Motion requests as a client builds them (edsp-ctl's fields), for tests of
// the planner's motion service.
#include <cstdint>
#include <string>

#include "edsp/kinematics/types.h"
#include "edsp/motion_request_t.hpp"

namespace test_support {

class MotionRequests {
 public:
  explicit MotionRequests(std::int64_t session_id) : session_id_(session_id) {}

  edsp::motion_request_t Make(std::int8_t kind, std::int64_t now_utime) {
    edsp::motion_request_t r{};
    r.utime = now_utime;
    r.seq = ++seq_;
    r.session_id = session_id_;
    r.request_id = ++id_;
    r.client = "test";
    r.kind = kind;
    return r;
  }
  edsp::motion_request_t Move(const edsp::Vector6& pose, std::int64_t now_utime, bool relative = false,
                              const std::string& frame = "") {
    edsp::motion_request_t r = Make(edsp::motion_request_t::KIND_MOVE, now_utime);
    for (int k = 0; k < 6; ++k) r.pose[k] = pose(k);
    r.relative = relative;
    r.frame = frame;
    return r;
  }
  edsp::motion_request_t Frame(const std::string& name, const edsp::Vector6& pose, std::int64_t now_utime) {
    edsp::motion_request_t r = Make(edsp::motion_request_t::KIND_FRAME, now_utime);
    r.frame = name;
    for (int k = 0; k < 6; ++k) r.pose[k] = pose(k);
    return r;
  }
  edsp::motion_request_t Pivot(const edsp::Vector3& c, std::int64_t now_utime) {
    edsp::motion_request_t r = Make(edsp::motion_request_t::KIND_PIVOT, now_utime);
    for (int k = 0; k < 3; ++k) r.point[k] = c(k);
    return r;
  }

 private:
  std::int64_t session_id_;
  std::int64_t seq_ = 0, id_ = 0;
};

}  // namespace test_support
