#pragma once
// Every EDSP_* channel, once: its name, message type, publisher and rate
// (docs/interfaces.md §1; a test holds the names and types of both to each
// other; publisher and rate are prose there, nominal here). The nodes
// publish and subscribe by these names; what needs the whole list is driven
// from kChannels and from the message types' list (message_types.h): the
// log summary's loss accounting, the CSV export, the decoders' fuzz target.
// A new channel is one row here (and its type there, if new).

#include <string_view>

namespace edsp::channel {

inline constexpr char kConfig[] = "EDSP_CONFIG";
inline constexpr char kSetpoint[] = "EDSP_SETPOINT";
inline constexpr char kLegCommand[] = "EDSP_LEG_COMMAND";
inline constexpr char kLegState[] = "EDSP_LEG_STATE";
inline constexpr char kPlatformState[] = "EDSP_PLATFORM_STATE";
inline constexpr char kTracker[] = "EDSP_TRACKER";
inline constexpr char kRigTruth[] = "EDSP_RIG_TRUTH";
inline constexpr char kStatus[] = "EDSP_STATUS";
inline constexpr char kFault[] = "EDSP_FAULT";
inline constexpr char kArm[] = "EDSP_ARM";
inline constexpr char kPrMode[] = "EDSP_PR_MODE";
inline constexpr char kCalibration[] = "EDSP_CALIBRATION";
inline constexpr char kReply[] = "EDSP_REPLY";
inline constexpr char kMotionRequest[] = "EDSP_MOTION_REQUEST";
inline constexpr char kMotionReply[] = "EDSP_MOTION_REPLY";
inline constexpr char kMotionStatus[] = "EDSP_MOTION_STATUS";
inline constexpr char kCueSetpoint[] = "EDSP_CUE_SETPOINT";
inline constexpr char kVehicle[] = "EDSP_VEHICLE";

// Whose seq numbers a channel carries: one publisher's (a gap is a lost
// message); several interleaved (every node's status and faults; the
// operator's requests, each edsp-ctl run numbering its own from 1 and
// repeating them until answered): no loss can be told across them; or the
// vehicle's numbering of its samples (EDSP_VEHICLE: a sample the cueing
// refused, or a network before it lost, is a gap the bus did not make).
enum class Publishers { kOne, kMany, kVehicleNumbering };

struct Channel {
  std::string_view name;
  std::string_view type;       // the LCM type, package edsp (getTypeName())
  std::string_view publisher;  // the node (or tool) that publishes it
  double rate_hz;              // nominal; 0: on event or on request
  Publishers publishers;
};

inline constexpr Channel kChannels[] = {
    {kConfig, "platform_config_t", "kinematics", 1.0, Publishers::kOne},
    {kSetpoint, "pose_setpoint_t", "planner", 1000.0, Publishers::kOne},
    {kLegCommand, "leg_command_t", "kinematics", 1000.0, Publishers::kOne},
    {kLegState, "leg_state_t", "actuator_bridge", 1000.0, Publishers::kOne},
    {kPlatformState, "platform_state_t", "kinematics", 100.0, Publishers::kOne},
    {kTracker, "tracker_point_t", "rig", 1000.0, Publishers::kOne},
    {kRigTruth, "rig_truth_t", "rig", 1000.0, Publishers::kOne},
    {kStatus, "node_status_t", "every node", 1.0, Publishers::kMany},
    {kFault, "fault_t", "any node", 0.0, Publishers::kMany},
    {kArm, "arm_t", "edsp-ctl", 0.0, Publishers::kMany},
    {kPrMode, "pr_mode_t", "edsp-ctl", 0.0, Publishers::kMany},
    {kCalibration, "calibration_t", "edsp-ctl", 0.0, Publishers::kMany},
    {kReply, "reply_t", "actuator_bridge, kinematics", 0.0, Publishers::kMany},
    {kMotionRequest, "motion_request_t", "edsp-ctl (any client)", 0.0, Publishers::kMany},
    {kMotionReply, "motion_reply_t", "planner", 0.0, Publishers::kOne},
    {kMotionStatus, "motion_status_t", "planner", 50.0, Publishers::kOne},
    {kCueSetpoint, "pose_setpoint_t", "cueing", 1000.0, Publishers::kOne},
    {kVehicle, "vehicle_motion_t", "the vehicle model (edsp-cueing send), or edsp-cueing live --input udp", 250.0,
     Publishers::kVehicleNumbering},
};

// The row of `name`, or null for a channel that is not edsp's.
constexpr const Channel* Find(std::string_view name) {
  for (const Channel& c : kChannels) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

// Several seq streams interleave on it (status, faults, operator requests).
constexpr bool HasManyPublishers(std::string_view name) {
  const Channel* c = Find(name);
  return c != nullptr && c->publishers == Publishers::kMany;
}

// True if a gap in edsp channel `name`'s seq says nothing of a message the
// bus lost (several publishers, or the vehicle's numbering).
constexpr bool SeqGapsAreNotLosses(std::string_view name) {
  const Channel* c = Find(name);
  return c != nullptr && c->publishers != Publishers::kOne;
}

}  // namespace edsp::channel
