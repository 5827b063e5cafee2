#pragma once
// Every edsp message type (lcmtypes/*.lcm), as a list code can iterate at
// compile time: the CSV export's decoders and the fuzz target's are driven
// from it, and a test holds it to the channel table (channels.h) and to
// lcmtypes/CMakeLists.txt.

#include <cstddef>
#include <tuple>
#include <utility>

#include "edsp/arm_t.hpp"
#include "edsp/arm_v1_t.hpp"
#include "edsp/calibration_t.hpp"
#include "edsp/calibration_v1_t.hpp"
#include "edsp/fault_t.hpp"
#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/motion_reply_t.hpp"
#include "edsp/motion_reply_v1_t.hpp"
#include "edsp/motion_request_t.hpp"
#include "edsp/motion_status_t.hpp"
#include "edsp/motion_status_v1_t.hpp"
#include "edsp/node_status_t.hpp"
#include "edsp/platform_config_t.hpp"
#include "edsp/platform_state_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/pose_setpoint_v1_t.hpp"
#include "edsp/pr_mode_t.hpp"
#include "edsp/pr_mode_v1_t.hpp"
#include "edsp/reply_t.hpp"
#include "edsp/rig_truth_t.hpp"
#include "edsp/tracker_point_t.hpp"
#include "edsp/vehicle_motion_t.hpp"

namespace edsp {

// The order is the fuzz corpus's: a seed's first byte picks the type by index.
using MessageTypes = std::tuple<pose_setpoint_t, leg_command_t, leg_state_t, platform_state_t, platform_config_t,
                                tracker_point_t, rig_truth_t, node_status_t, fault_t, arm_t, pr_mode_t, calibration_t,
                                motion_request_t, motion_reply_t, motion_status_t, reply_t, vehicle_motion_t>;
inline constexpr std::size_t kMessageTypeCount = std::tuple_size_v<MessageTypes>;

// Older layouts of changed types (lcmtypes/legacy/), read from the logs
// that carry them and never sent: a log's reader knows them by fingerprint.
using LegacyMessageTypes =
    std::tuple<arm_v1_t, pr_mode_v1_t, calibration_v1_t, motion_reply_v1_t, motion_status_v1_t, pose_setpoint_v1_t>;

// A message type as a value, for the visitors below.
template <typename Msg>
struct TypeTag {
  using type = Msg;
};

namespace detail {
template <typename Types, typename F, std::size_t... I>
void ForEachMessageType(F&& f, std::index_sequence<I...>) {
  (f(TypeTag<std::tuple_element_t<I, Types>>{}), ...);
}
template <typename F, std::size_t... I>
void VisitMessageType(std::size_t index, F&& f, std::index_sequence<I...>) {
  ((index == I ? (f(TypeTag<std::tuple_element_t<I, MessageTypes>>{}), 0) : 0), ...);
}
}  // namespace detail

// f(TypeTag<Msg>{}) for every message type, in MessageTypes' order.
template <typename F>
void ForEachMessageType(F&& f) {
  detail::ForEachMessageType<MessageTypes>(std::forward<F>(f), std::make_index_sequence<kMessageTypeCount>{});
}

// The same for the message types and then the legacy ones: what a log may hold.
template <typename F>
void ForEachLoggedMessageType(F&& f) {
  ForEachMessageType(f);
  detail::ForEachMessageType<LegacyMessageTypes>(std::forward<F>(f),
                                                 std::make_index_sequence<std::tuple_size_v<LegacyMessageTypes>>{});
}

// f(TypeTag<Msg>{}) for the type at `index` (< kMessageTypeCount; else nothing).
template <typename F>
void VisitMessageType(std::size_t index, F&& f) {
  detail::VisitMessageType(index, std::forward<F>(f), std::make_index_sequence<kMessageTypeCount>{});
}

}  // namespace edsp
