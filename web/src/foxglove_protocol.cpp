#include "edsp/web/foxglove_protocol.h"

#include <limits>

namespace edsp::web::foxglove {
namespace {

using nlohmann::json;

void AppendLittleEndian(std::string* out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out->push_back(static_cast<char>((value >> (8 * i)) & 0xffu));
}

std::uint32_t RequireId(const json& object, const char* key, const char* op) {
  const auto it = object.find(key);
  if (it == object.end()) throw ProtocolError(std::string(op) + ": no \"" + key + "\"");
  if (!it->is_number_unsigned() || it->get<std::uint64_t>() > std::numeric_limits<std::uint32_t>::max()) {
    throw ProtocolError(std::string(op) + ": \"" + key + "\" is " + it->dump() + ", not a 32-bit unsigned integer");
  }
  return it->get<std::uint32_t>();
}

const json& RequireArray(const json& frame, const char* key, const char* op, std::size_t max_items) {
  const auto it = frame.find(key);
  if (it == frame.end() || !it->is_array()) throw ProtocolError(std::string(op) + ": \"" + key + "\" is not an array");
  if (it->size() > max_items) {
    throw ProtocolError(std::string(op) + ": " + std::to_string(it->size()) + " items in \"" + key + "\" (at most " +
                        std::to_string(max_items) + ")");
  }
  return *it;
}

}  // namespace

std::string ServerInfo(std::string_view name, std::string_view session_id, const json& metadata) {
  return json{{"op", "serverInfo"},
              {"name", name},
              {"capabilities", json::array()},
              {"metadata", metadata},
              {"sessionId", session_id}}
      .dump();
}

std::string Status(StatusLevel level, std::string_view message) {
  return json{{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}.dump();
}

std::string Advertise(const std::vector<ServerChannel>& channels) {
  json list = json::array();
  for (const ServerChannel& c : channels) {
    list.push_back({{"id", c.id},
                    {"topic", c.topic},
                    {"encoding", "json"},
                    {"schemaName", c.schema_name},
                    {"schema", c.schema.dump()},
                    {"schemaEncoding", "jsonschema"}});
  }
  return json{{"op", "advertise"}, {"channels", std::move(list)}}.dump();
}

std::string MessageData(std::uint32_t subscription_id, std::uint64_t receive_ns, std::string_view payload) {
  std::string frame;
  frame.reserve(13 + payload.size());
  frame.push_back(static_cast<char>(kMessageDataOpcode));
  AppendLittleEndian(&frame, subscription_id, 4);
  AppendLittleEndian(&frame, receive_ns, 8);
  frame.append(payload);
  return frame;
}

ClientOp ParseClientText(std::string_view text, std::size_t max_items) {
  const json frame = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (frame.is_discarded()) throw ProtocolError("a text frame that is not JSON");
  if (!frame.is_object()) throw ProtocolError("a text frame that is not a JSON object");
  const auto op = frame.find("op");
  if (op == frame.end() || !op->is_string()) throw ProtocolError("a text frame without a string \"op\"");
  ClientOp parsed;
  if (*op == "subscribe") {
    parsed.kind = ClientOp::kSubscribe;
    for (const json& s : RequireArray(frame, "subscriptions", "subscribe", max_items)) {
      if (!s.is_object()) throw ProtocolError("subscribe: a subscription that is not an object");
      parsed.subscriptions.push_back({RequireId(s, "id", "subscribe"), RequireId(s, "channelId", "subscribe")});
    }
  } else if (*op == "unsubscribe") {
    parsed.kind = ClientOp::kUnsubscribe;
    for (const json& id : RequireArray(frame, "subscriptionIds", "unsubscribe", max_items)) {
      parsed.ids.push_back(RequireId(json{{"id", id}}, "id", "unsubscribe"));
    }
  } else {
    throw ProtocolError("op \"" + op->get<std::string>() + "\" is not one this server takes (subscribe, unsubscribe)");
  }
  return parsed;
}

}  // namespace edsp::web::foxglove
