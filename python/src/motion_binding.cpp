// edsp.Platform's core: the planner's motion service and the operator's
// requests, through the client edsp-ctl uses (planner/motion_client.h,
// node/operator_client.h) on edsp's Bus.
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "bindings.h"
#include "edsp/arm_t.hpp"
#include "edsp/calibration_t.hpp"
#include "edsp/channels.h"
#include "edsp/node/group_file.h"
#include "edsp/node/operator_client.h"
#include "edsp/planner/motion_client.h"
#include "edsp/pr_mode_t.hpp"

namespace edsp::python {

namespace {

py::dict ReplyDict(const motion_reply_t& r) {
  py::dict d;
  d["accepted"] = r.accepted != 0;
  d["reason"] = r.reason;
  d["duration_s"] = r.duration_s;
  d["start_delay_s"] = r.start_delay_s;
  d["request_id"] = r.request_id;
  return d;
}

template <std::size_t N>
py::array_t<double> Array(const double (&v)[N]) {
  py::array_t<double> a(static_cast<py::ssize_t>(N));
  for (std::size_t k = 0; k < N; ++k) a.mutable_data()[k] = v[k];
  return a;
}

py::dict StatusDict(const motion_status_t& s) {
  py::dict d;
  d["state"] = MotionStateName(s.state);
  d["on_target"] = s.on_target != 0;
  d["request_id"] = s.request_id;
  d["activity"] = s.activity;
  d["progress"] = s.progress;
  d["queued"] = s.queued;
  d["last_end"] = MotionEndName(s.last_end);
  d["pose_commanded"] = Array(s.pose_commanded);
  d["pose_target"] = Array(s.pose_target);
  d["pose_measured"] = Array(s.pose_measured);
  d["measured_valid"] = s.measured_valid != 0;
  d["frame"] = s.frame;
  d["pivot"] = Array(s.pivot);
  d["reason"] = s.reason;
  d["session_id"] = s.session_id;
  d["utime"] = s.utime;
  return d;
}

// The motion service's client, with the request built from keywords. One
// Bus serves every call, so calls from several Python threads take turns
// (a halt from another thread waits at most one slice of a wait); a wait
// goes in slices of 0.1 s and answers Ctrl-C between them.
class Client {
 public:
  Client(const std::string& group_file, const std::string& lcm_url, std::optional<std::int64_t> session_id,
         double answer_timeout_s, const std::string& client_name)
      : client_(Transport(group_file, lcm_url), session_id, answer_timeout_s, client_name) {}

  std::int64_t session_id() const { return client_.session_id(); }

  py::dict Send(int kind, const std::vector<double>& pose, bool relative, const std::string& frame,
                const std::vector<double>& point, double speed_m_s, double speed_rad_s, double accel_m_s2,
                double accel_rad_s2, const std::string& motions, const std::string& csv_text,
                const std::string& csv_origin) {
    motion_request_t r = client_.Request(static_cast<std::int8_t>(kind));
    for (std::size_t k = 0; k < 6 && k < pose.size(); ++k) r.pose[k] = pose[k];
    for (std::size_t k = 0; k < 3 && k < point.size(); ++k) r.point[k] = point[k];
    r.relative = relative;
    r.frame = frame;
    r.speed_m_s = speed_m_s, r.speed_rad_s = speed_rad_s;
    r.accel_m_s2 = accel_m_s2, r.accel_rad_s2 = accel_rad_s2;
    r.motions = motions, r.csv_text = csv_text, r.csv_origin = csv_origin;
    std::optional<motion_reply_t> reply;
    {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(mutex_);
      reply = client_.Send(r);
    }
    if (!reply) return py::dict();
    return ReplyDict(*reply);
  }

  std::optional<py::dict> Status(double timeout_s) {
    std::optional<motion_status_t> s;
    {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(mutex_);
      s = client_.NextStatus(timeout_s);
    }
    if (!s) return std::nullopt;
    return StatusDict(*s);
  }

  // An operator's request to a node, as edsp-ctl sends it: (answered,
  // confirmed, the node's words).
  std::tuple<bool, bool, std::string> Arm() {
    arm_t request{};
    return Operator(channel::kArm, request, "actuator_bridge");
  }
  std::tuple<bool, bool, std::string> PrMode(const std::string& mode_text) {
    pr_mode_t request{};
    request.pr_mode = static_cast<std::int8_t>(ModeOf(mode_text));
    return Operator(channel::kPrMode, request, "kinematics");
  }
  std::tuple<bool, bool, std::string> Calibration(const std::string& model_json, const std::string& origin,
                                                  bool apply_ambiguous) {
    calibration_t request{};
    request.model_json = model_json;
    request.origin = origin;
    request.apply_ambiguous = apply_ambiguous ? 1 : 0;
    return Operator(channel::kCalibration, request, "kinematics");
  }

  // (outcome, message): "on_target", "halted", "fault" or "timeout".
  std::pair<std::string, std::string> Wait(std::int64_t request_id, double timeout_s) {
    constexpr double kSlice_s = 0.1;
    WaitResult r;
    bool seen = false;
    const auto until =
        std::chrono::steady_clock::now() +
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeout_s));
    while (true) {
      const double left = std::chrono::duration<double>(until - std::chrono::steady_clock::now()).count();
      {
        py::gil_scoped_release release;
        const std::lock_guard<std::mutex> lock(mutex_);
        r = client_.Wait(request_id, std::max(0.0, std::min(kSlice_s, left)), &seen);
      }
      if (r.outcome != WaitOutcome::kTimedOut || left <= kSlice_s) break;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
    if (r.outcome == WaitOutcome::kTimedOut) r.message = fmt::format("not on target within {} s", timeout_s);
    switch (r.outcome) {
      case WaitOutcome::kOnTarget: return {"on_target", ""};
      case WaitOutcome::kHaltedOrStopped: return {"halted", r.message};
      case WaitOutcome::kFault: return {"fault", r.message};
      case WaitOutcome::kTimedOut: return {"timeout", r.message};
    }
    return {"timeout", r.message};
  }

 private:
  template <typename Msg>
  std::tuple<bool, bool, std::string> Operator(const char* channel, Msg request, const std::string& node) {
    request.session_id = client_.session_id();
    request.operator_name = client_.client_name();
    OperatorAnswer answer;
    {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(mutex_);
      answer = SendOperatorRequest(client_.bus(), channel, request, node, client_.answer_timeout_s());
    }
    return {answer.given, answer.confirmed, answer.reason};
  }

  static TransportConfig Transport(const std::string& group_file, const std::string& lcm_url) {
    TransportConfig config = group_file.empty() ? TransportConfig{} : LoadTransportConfig(group_file);
    if (!lcm_url.empty()) config.lcm_url = lcm_url;
    config.channels.clear();  // requests, replies and status travel on LCM
    return config;
  }

  MotionClient client_;
  std::mutex mutex_;
};

}  // namespace

void BindMotion(py::module_& m) {
  py::class_<Client>(m, "Client")
      .def(py::init<const std::string&, const std::string&, std::optional<std::int64_t>, double, const std::string&>(),
           py::arg("group_file"), py::arg("lcm_url"), py::arg("session_id"), py::arg("answer_timeout_s"),
           py::arg("client_name"))
      .def_property_readonly("session_id", &Client::session_id)
      .def("send", &Client::Send)
      .def("status", &Client::Status)
      .def("wait", &Client::Wait)
      .def("arm", &Client::Arm)
      .def("pr_mode", &Client::PrMode)
      .def("calibration", &Client::Calibration);
  m.attr("KIND_MOVE") = motion_request_t::KIND_MOVE;
  m.attr("KIND_CHECK") = motion_request_t::KIND_CHECK;
  m.attr("KIND_RUN") = motion_request_t::KIND_RUN;
  m.attr("KIND_HALT") = motion_request_t::KIND_HALT;
  m.attr("KIND_STOP") = motion_request_t::KIND_STOP;
  m.attr("KIND_FRAME") = motion_request_t::KIND_FRAME;
  m.attr("KIND_PIVOT") = motion_request_t::KIND_PIVOT;
  m.attr("KIND_LIMITS") = motion_request_t::KIND_LIMITS;
}

}  // namespace edsp::python
