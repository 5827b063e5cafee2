#pragma once
// An operator's request, as a browser writes it (JSON with the .lcm field
// names, as edsp-web sends messages), into the request channel's message
// type, field by field through the same table (message_fields.h). Every key
// must be a field of the type, each value of the field's JSON type and
// shape (integers in their type's range, finite numbers, arrays of their
// exact length; a boolean for an int8 field is 0 or 1); an absent field
// stays zero or empty.

#include <string>
#include <string_view>
#include <variant>

#include "edsp/arm_t.hpp"
#include "edsp/calibration_t.hpp"
#include "edsp/motion_request_t.hpp"
#include "edsp/pr_mode_t.hpp"

namespace edsp::web {

// What an operator's client may publish, one type per request channel.
using RequestMessage = std::variant<motion_request_t, arm_t, pr_mode_t, calibration_t>;

// Whether `channel` is one a client may publish on (EDSP_MOTION_REQUEST,
// EDSP_ARM, EDSP_PR_MODE, EDSP_CALIBRATION).
bool IsRequestChannel(std::string_view channel);

// The request in `json_text` for `channel`. Throws foxglove::ProtocolError
// naming the channel, the field and what is wrong with it.
RequestMessage RequestFromJson(std::string_view channel, std::string_view json_text);

}  // namespace edsp::web
