// edsp.Platform's core: the planner's motion service and the operator's
// requests, through the client edsp-ctl uses (planner/motion_client.h,
// node/request_client.h) on edsp's Bus.
#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bindings.h"
#include "errors.h"
#include "edsp/arm_t.hpp"
#include "edsp/calibration_t.hpp"
#include "edsp/channels.h"
#include "edsp/node/group_file.h"
#include "edsp/node/session_discovery.h"
#include "edsp/planner/motion_client.h"
#include "edsp/planner/motion_request_checks.h"
#include "edsp/pr_mode_t.hpp"
#include "edsp/reply_codes.h"
#include "edsp/request_kinds.h"

namespace edsp::python {

namespace {

std::string CodeName(std::int8_t code) { return std::string(ReplyCodeName(code)); }

// A reply that is not "done" as the exception of its family.
void RaiseUnlessDone(std::int8_t code, const std::string& reason) {
  switch (FamilyOf(code)) {
    case ReplyFamily::kDone: return;
    case ReplyFamily::kRefused: throw RequestError(ErrorFamily::kRefused, CodeName(code), reason);
    case ReplyFamily::kFailed: throw RequestError(ErrorFamily::kFault, CodeName(code), reason);
  }
}

py::dict ReplyDict(const motion_reply_t& r) {
  py::dict d;
  d["accepted"] = r.accepted != 0;
  d["code"] = CodeName(r.code);
  d["reason"] = r.reason;
  d["duration_s"] = r.duration_s;
  d["start_delay_s"] = r.start_delay_s;
  d["request_id"] = r.request_id;
  return d;
}

py::dict ReplyDict(const reply_t& r) {
  py::dict d;
  d["node"] = r.node;
  d["code"] = CodeName(r.code);
  d["reason"] = r.reason;
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
  d["frame_pose"] = Array(s.frame_pose);
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
      : client_(Connect(group_file, lcm_url, session_id, answer_timeout_s, client_name)) {}

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
    if (!reply) {
      throw RequestError(ErrorFamily::kTimeout, "timeout",
                         "no reply from the planner (is the group running, its planner serving requests?)");
    }
    RaiseUnlessDone(reply->code, reply->reason);
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

  // An operator's request to a node, as edsp-ctl sends it: the node's
  // reply, or the exception of its family.
  py::dict Arm() { return Operator(channel::kArm, arm_t{}); }
  py::dict SetPrMode(const std::string& mode_text) {
    pr_mode_t request{};
    request.pr_mode = static_cast<std::int8_t>(ModeOf(mode_text));
    return Operator(channel::kPrMode, request);
  }
  py::dict Calibration(const std::string& model_json, const std::string& origin, bool apply_ambiguous) {
    calibration_t request{};
    request.model_json = model_json;
    request.origin = origin;
    request.apply_ambiguous = apply_ambiguous ? 1 : 0;
    return Operator(channel::kCalibration, request);
  }

  // Until motion `request_id` (0: whatever runs) is on target (returned);
  // else the exception of the outcome (halted, fault, timeout).
  WaitOutcome Wait(std::int64_t request_id, double timeout_s) {
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
    switch (r.outcome) {
      case WaitOutcome::kOnTarget: return r.outcome;
      case WaitOutcome::kHaltedOrStopped: throw RequestError(ErrorFamily::kHalted, "halted", r.message);
      case WaitOutcome::kFault: throw RequestError(ErrorFamily::kFault, "fault", r.message);
      case WaitOutcome::kTimedOut: break;
    }
    throw RequestError(ErrorFamily::kTimeout, "timeout", fmt::format("not on target within {} s", timeout_s));
  }

 private:
  template <typename Msg>
  py::dict Operator(const char* channel, const Msg& request) {
    std::optional<reply_t> reply;
    {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(mutex_);
      reply = client_.SendOperator(channel, request);
    }
    if (!reply) {
      throw RequestError(ErrorFamily::kTimeout, "timeout",
                         fmt::format("no reply on EDSP_REPLY to {} within {} s (is the group running?)", channel,
                                     client_.answer_timeout_s()));
    }
    RaiseUnlessDone(reply->code, reply->reason);
    return ReplyDict(*reply);
  }

  // No group (or several) on the bus is a wait that ran out.
  static MotionClient Connect(const std::string& group_file, const std::string& lcm_url,
                              std::optional<std::int64_t> session_id, double answer_timeout_s,
                              const std::string& client_name) {
    try {
      return MotionClient(Transport(group_file, lcm_url), session_id, answer_timeout_s, client_name);
    } catch (const SessionNotFound& e) {
      throw RequestError(ErrorFamily::kTimeout, "no_session", e.what());
    }
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
      .def("pr_mode", &Client::SetPrMode)
      .def("calibration", &Client::Calibration);
  // A jog's axes in a pose's order, as the planner checks them.
  m.attr("JOG_AXES") = py::make_tuple(kJogAxes[0], kJogAxes[1], kJogAxes[2], kJogAxes[3], kJogAxes[4], kJogAxes[5]);
  // KIND_MOVE, KIND_CHECK, …: one per row of request_kinds.h.
  for (const RequestKindRow& row : kRequestKinds) {
    std::string name = "KIND_" + std::string(row.name);
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::toupper(c); });
    m.attr(name.c_str()) = row.kind;
  }
  py::enum_<WaitOutcome>(m, "WaitOutcome", "How a wait for a motion ended (planner/motion_client.h).")
      .value("ON_TARGET", WaitOutcome::kOnTarget)
      .value("HALTED_OR_STOPPED", WaitOutcome::kHaltedOrStopped)
      .value("FAULT", WaitOutcome::kFault)
      .value("TIMED_OUT", WaitOutcome::kTimedOut);
}

}  // namespace edsp::python
