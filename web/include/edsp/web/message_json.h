#pragma once
// edsp's messages as JSON for the browser, field for field with the .lcm
// types' names (message_fields.h: the table the CSV export and the Python
// package use), and each type's JSON schema, generated from the same table:
// a field a .lcm file gains appears in both without a line here.
//   int8/int32/int64 → "integer", double → "number" (NaN and infinities,
//   which JSON cannot carry, become null; the schema allows it), string →
//   "string", fixed-size arrays → "array" of exactly their length (matrices
//   as arrays of arrays).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace edsp::web {

// `data` (an LCM message of any edsp type, known by its fingerprint) as a
// JSON object, its fields in the .lcm file's order; false for a foreign
// fingerprint or bytes that do not decode. `type` gets "edsp.<type>".
bool MessageToJson(const std::uint8_t* data, std::size_t size, nlohmann::ordered_json* out,
                   std::string* type = nullptr);

// The JSON schema (draft 2020-12) of the message type named `type_name`
// ("pose_setpoint_t", as channels.h names them): an object with every field
// required, in order. Throws std::invalid_argument for a name not edsp's.
nlohmann::ordered_json MessageSchema(std::string_view type_name);

}  // namespace edsp::web
