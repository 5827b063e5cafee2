#pragma once
// Every field of every edsp message type (message_types.h), in the .lcm
// files' order, for code that handles messages field by field without
// knowing their types: the log's CSV export, the Python package's numpy
// columns. VisitFields(msg, &v) calls v->Add(name, value) once per field,
// with value an int8/int32/int64, a double, a std::string or a fixed-size
// array of them (arrays of arrays for matrices). A message type without an
// overload here does not compile where every type is visited.

#include <type_traits>

#include "edsp/message_types.h"

namespace edsp {

// pose_setpoint_t and its older layout, which has no phase.
template <typename Setpoint, typename V>
void VisitSetpointFields(const Setpoint& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("pose", m.pose), r->Add("velocity", m.velocity), r->Add("acceleration", m.acceleration);
  r->Add("trajectory", m.trajectory), r->Add("segment", m.segment);
  if constexpr (std::is_same_v<Setpoint, pose_setpoint_t>) r->Add("phase", m.phase);
}
template <typename V>
void VisitFields(const pose_setpoint_t& m, V* r) {
  VisitSetpointFields(m, r);
}
template <typename V>
void VisitFields(const leg_command_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("setpoint_utime", m.setpoint_utime), r->Add("setpoint_seq", m.setpoint_seq);
  r->Add("pr_mode", m.pr_mode), r->Add("ik_length_m", m.ik_length_m);
  r->Add("pr_correction_m", m.pr_correction_m), r->Add("command_length_m", m.command_length_m);
  r->Add("motor_angle_rad", m.motor_angle_rad);
}
template <typename V>
void VisitFields(const leg_state_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("command_seq", m.command_seq);
  r->Add("motor_angle_rad", m.motor_angle_rad), r->Add("motor_velocity_rad_s", m.motor_velocity_rad_s);
  r->Add("encoder_length_m", m.encoder_length_m), r->Add("drive_status", m.drive_status);
}
template <typename V>
void VisitFields(const platform_state_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("pose", m.pose);
  r->Add("target_pose", m.target_pose), r->Add("observation_point_m", m.observation_point_m);
  r->Add("fk_status", m.fk_status), r->Add("fk_residual_m", m.fk_residual_m);
}
template <typename V>
void VisitFields(const platform_config_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("preset", m.preset);
  r->Add("base_joints_m", m.base_joints_m), r->Add("platform_joints_m", m.platform_joints_m);
  r->Add("base_axes", m.base_axes), r->Add("platform_axes", m.platform_axes);
  r->Add("home_height_m", m.home_height_m), r->Add("lead_m", m.lead_m);
  r->Add("pr_sign", m.pr_sign), r->Add("gear_ratio", m.gear_ratio);
  r->Add("leg_min_m", m.leg_min_m), r->Add("leg_max_m", m.leg_max_m);
  r->Add("joint_angle_max_rad", m.joint_angle_max_rad);
  r->Add("observation_point_m", m.observation_point_m), r->Add("config_toml", m.config_toml);
}
template <typename V>
void VisitFields(const tracker_point_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("point_m", m.point_m);
  r->Add("sigma_m", m.sigma_m), r->Add("valid", m.valid);
}
template <typename V>
void VisitFields(const rig_truth_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("pose", m.pose);
  r->Add("leg_length_m", m.leg_length_m), r->Add("twist_rad", m.twist_rad);
  r->Add("observation_point_m", m.observation_point_m);
}
template <typename V>
void VisitFields(const node_status_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("node", m.node), r->Add("pid", m.pid);
  r->Add("state", m.state), r->Add("messages_in", m.messages_in);
  r->Add("messages_out", m.messages_out), r->Add("drops", m.drops);
  r->Add("rejected", m.rejected), r->Add("deadline_misses", m.deadline_misses);
  r->Add("loop_p50_us", m.loop_p50_us), r->Add("loop_p99_us", m.loop_p99_us);
  r->Add("loop_max_us", m.loop_max_us);
}
template <typename V>
void VisitFields(const fault_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("node", m.node);
  r->Add("channel", m.channel), r->Add("severity", m.severity), r->Add("code", m.code);
  r->Add("reason", m.reason);
}
template <typename V>
void VisitFields(const arm_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id);
  r->Add("operator_name", m.operator_name);
}
template <typename V>
void VisitFields(const pr_mode_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id);
  r->Add("pr_mode", m.pr_mode), r->Add("operator_name", m.operator_name);
}
template <typename V>
void VisitFields(const calibration_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id);
  r->Add("operator_name", m.operator_name), r->Add("origin", m.origin), r->Add("model_json", m.model_json);
  r->Add("apply_ambiguous", m.apply_ambiguous);
}

template <typename V>
void VisitFields(const motion_request_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id), r->Add("client", m.client), r->Add("kind", m.kind);
  r->Add("relative", m.relative), r->Add("frame", m.frame), r->Add("pose", m.pose), r->Add("point", m.point);
  r->Add("speed_m_s", m.speed_m_s), r->Add("speed_rad_s", m.speed_rad_s);
  r->Add("accel_m_s2", m.accel_m_s2), r->Add("accel_rad_s2", m.accel_rad_s2);
  r->Add("motions", m.motions), r->Add("csv_text", m.csv_text), r->Add("csv_origin", m.csv_origin);
}

template <typename V>
void VisitFields(const motion_reply_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id), r->Add("kind", m.kind), r->Add("accepted", m.accepted);
  r->Add("code", m.code), r->Add("reason", m.reason), r->Add("duration_s", m.duration_s),
      r->Add("start_delay_s", m.start_delay_s);
}

template <typename V>
void VisitFields(const reply_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id), r->Add("node", m.node), r->Add("request_channel", m.request_channel);
  r->Add("code", m.code), r->Add("reason", m.reason);
}

template <typename V>
void VisitFields(const vehicle_motion_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("command", m.command), r->Add("time_s", m.time_s);
  r->Add("specific_force", m.specific_force), r->Add("angular_velocity", m.angular_velocity);
  r->Add("has_angular_acceleration", m.has_angular_acceleration);
  r->Add("angular_acceleration", m.angular_acceleration);
}

// The older layouts, field for field as they were.
template <typename V>
void VisitFields(const arm_v1_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("operator_name", m.operator_name);
}
template <typename V>
void VisitFields(const pr_mode_v1_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("pr_mode", m.pr_mode), r->Add("operator_name", m.operator_name);
}
template <typename V>
void VisitFields(const calibration_v1_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("operator_name", m.operator_name), r->Add("origin", m.origin), r->Add("model_json", m.model_json);
  r->Add("apply_ambiguous", m.apply_ambiguous);
}
template <typename V>
void VisitFields(const motion_reply_v1_t& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id), r->Add("kind", m.kind), r->Add("accepted", m.accepted);
  r->Add("reason", m.reason), r->Add("duration_s", m.duration_s), r->Add("start_delay_s", m.start_delay_s);
}

// motion_status_t and its older layout, which has no frame_pose.
template <typename Status, typename V>
void VisitMotionStatusFields(const Status& m, V* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("state", m.state), r->Add("request_id", m.request_id), r->Add("activity", m.activity);
  r->Add("progress", m.progress), r->Add("queued", m.queued), r->Add("last_end", m.last_end);
  r->Add("pose_commanded", m.pose_commanded), r->Add("pose_target", m.pose_target);
  r->Add("pose_measured", m.pose_measured), r->Add("measured_valid", m.measured_valid);
  r->Add("on_target", m.on_target), r->Add("frame", m.frame);
  if constexpr (std::is_same_v<Status, motion_status_t>) r->Add("frame_pose", m.frame_pose);
  r->Add("pivot", m.pivot), r->Add("reason", m.reason);
}
template <typename V>
void VisitFields(const pose_setpoint_v1_t& m, V* r) {
  VisitSetpointFields(m, r);
}
template <typename V>
void VisitFields(const motion_status_v1_t& m, V* r) {
  VisitMotionStatusFields(m, r);
}
template <typename V>
void VisitFields(const motion_status_t& m, V* r) {
  VisitMotionStatusFields(m, r);
}

}  // namespace edsp
