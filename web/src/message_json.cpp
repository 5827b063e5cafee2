#include "edsp/web/message_json.h"

#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "edsp/logger/edsp_message.h"
#include "edsp/message_fields.h"
#include "edsp/message_types.h"

namespace edsp::web {
namespace {

using json = nlohmann::ordered_json;

template <typename T>
json FieldValue(const T& v) {
  if constexpr (std::is_array_v<T>) {
    json items = json::array();
    for (const auto& element : v) items.push_back(FieldValue(element));
    return items;
  } else if constexpr (std::is_same_v<T, double>) {
    return std::isfinite(v) ? json(v) : json(nullptr);
  } else if constexpr (std::is_integral_v<T>) {
    return json(static_cast<std::int64_t>(v));  // int8 as a number, not a character
  } else {
    static_assert(std::is_same_v<T, std::string>, "a field type message_json.h does not know");
    return json(v);
  }
}

template <typename T>
json FieldSchema() {
  if constexpr (std::is_array_v<T>) {
    constexpr std::size_t n = std::extent_v<T>;
    return {{"type", "array"}, {"items", FieldSchema<std::remove_extent_t<T>>()}, {"minItems", n}, {"maxItems", n}};
  } else if constexpr (std::is_same_v<T, double>) {
    return {{"type", json::array({"number", "null"})}};
  } else if constexpr (std::is_integral_v<T>) {
    return {{"type", "integer"}};
  } else {
    static_assert(std::is_same_v<T, std::string>, "a field type message_json.h does not know");
    return {{"type", "string"}};
  }
}

struct JsonFields {
  json* out;
  template <typename T>
  void Add(const char* name, const T& value) {
    (*out)[name] = FieldValue(value);
  }
};

struct SchemaFields {
  json* properties;
  json* required;
  template <typename T>
  void Add(const char* name, const T&) {
    (*properties)[name] = FieldSchema<T>();
    required->push_back(name);
  }
};

}  // namespace

bool MessageToJson(const std::uint8_t* data, std::size_t size, json* out, std::string* type) {
  return DecodeEdspMessage(data, size, [&](const auto& msg, const std::string& type_name) {
    *out = json::object();
    JsonFields fields{out};
    VisitFields(msg, &fields);
    if (type != nullptr) *type = type_name;
  });
}

json MessageSchema(std::string_view type_name) {
  json schema;
  ForEachMessageType([&](auto tag) {
    using Msg = typename decltype(tag)::type;
    if (!schema.is_null() || type_name != Msg::getTypeName()) return;
    json properties = json::object();
    json required = json::array();
    SchemaFields fields{&properties, &required};
    VisitFields(Msg{}, &fields);
    schema = {{"$schema", "https://json-schema.org/draft/2020-12/schema"},
              {"title", std::string("edsp.") + Msg::getTypeName()},
              {"type", "object"},
              {"properties", std::move(properties)},
              {"required", std::move(required)}};
  });
  if (schema.is_null()) throw std::invalid_argument("no edsp message type " + std::string(type_name));
  return schema;
}

}  // namespace edsp::web
