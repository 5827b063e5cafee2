#include "edsp/web/request_json.h"

#include <cmath>
#include <limits>
#include <set>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "edsp/channels.h"
#include "edsp/message_fields.h"
#include "edsp/web/foxglove_protocol.h"

namespace edsp::web {
namespace {

using foxglove::ProtocolError;
using JsonValue = nlohmann::json;

template <typename T>
void Assign(T& field, const JsonValue& value, const std::string& where) {
  if constexpr (std::is_array_v<T>) {
    constexpr std::size_t n = std::extent_v<T>;
    if (!value.is_array() || value.size() != n) {
      throw ProtocolError(where + " must be an array of " + std::to_string(n) + ", not " + value.dump());
    }
    for (std::size_t i = 0; i < n; ++i) Assign(field[i], value[i], where + "[" + std::to_string(i) + "]");
  } else if constexpr (std::is_same_v<T, double>) {
    if (!value.is_number()) throw ProtocolError(where + " must be a number, not " + value.dump());
    field = value.get<double>();
    if (!std::isfinite(field)) throw ProtocolError(where + " must be finite, not " + value.dump());
  } else if constexpr (std::is_integral_v<T>) {
    if (value.is_boolean() && std::is_same_v<T, std::int8_t>) {
      field = value.get<bool>() ? 1 : 0;
      return;
    }
    const bool fits = value.is_number_integer() &&
                      (value.is_number_unsigned()
                           ? value.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<T>::max())
                           : value.get<std::int64_t>() >= std::numeric_limits<T>::min() &&
                                 value.get<std::int64_t>() <= std::numeric_limits<T>::max());
    if (!fits) throw ProtocolError(where + " must be an integer that fits its type, not " + value.dump());
    field = static_cast<T>(value.get<std::int64_t>());
  } else {
    static_assert(std::is_same_v<T, std::string>, "a field type request_json.h does not know");
    if (!value.is_string()) throw ProtocolError(where + " must be a string, not " + value.dump());
    field = value.get<std::string>();
  }
}

// Writes through the field table, which is written for reading (it takes a
// const message): the message written is this function's own, never const.
struct FieldsFromJson {
  const JsonValue* object;
  std::string channel;
  std::set<std::string> known;
  template <typename T>
  void Add(const char* name, const T& field) {
    known.insert(name);
    const auto it = object->find(name);
    if (it != object->end()) Assign(const_cast<T&>(field), *it, channel + " " + name);
  }
};

template <typename Msg>
RequestMessage Parse(std::string_view channel, const JsonValue& object) {
  Msg msg{};
  FieldsFromJson fields{&object, std::string(channel), {}};
  VisitFields(msg, &fields);
  for (const auto& item : object.items()) {
    if (fields.known.count(item.key()) == 0) {
      throw ProtocolError(std::string(channel) + ": " + Msg::getTypeName() + " has no field \"" + item.key() + "\"");
    }
  }
  return msg;
}

}  // namespace

bool IsRequestChannel(std::string_view channel) {
  return channel == channel::kMotionRequest || channel == channel::kArm || channel == channel::kPrMode ||
         channel == channel::kCalibration;
}

RequestMessage RequestFromJson(std::string_view channel, std::string_view json_text) {
  foxglove::RequireShallowJson(json_text, foxglove::kMaxJsonDepth);
  const JsonValue object = JsonValue::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (object.is_discarded() || !object.is_object()) {
    throw ProtocolError(std::string(channel) + ": the message is not a JSON object");
  }
  if (channel == channel::kMotionRequest) return Parse<motion_request_t>(channel, object);
  if (channel == channel::kArm) return Parse<arm_t>(channel, object);
  if (channel == channel::kPrMode) return Parse<pr_mode_t>(channel, object);
  if (channel == channel::kCalibration) return Parse<calibration_t>(channel, object);
  throw ProtocolError(std::string(channel) +
                      " is not a request channel (EDSP_MOTION_REQUEST, EDSP_ARM, EDSP_PR_MODE, EDSP_CALIBRATION)");
}

}  // namespace edsp::web
