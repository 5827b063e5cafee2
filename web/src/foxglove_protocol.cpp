#include "edsp/web/foxglove_protocol.h"

#include <limits>

namespace edsp::web::foxglove {
namespace {

using nlohmann::json;

void AppendLittleEndian(std::string* out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out->push_back(static_cast<char>((value >> (8 * i)) & 0xffu));
}

std::string RequireString(const json& object, const char* key, const char* op) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_string())
    throw ProtocolError(std::string(op) + ": \"" + key + "\" is not a string");
  return it->get<std::string>();
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

std::string ServerInfo(std::string_view name, std::string_view session_id, const json& metadata, bool client_publish) {
  json info = {{"op", "serverInfo"},
               {"name", name},
               {"capabilities", client_publish ? json::array({"clientPublish"}) : json::array()},
               {"metadata", metadata},
               {"sessionId", session_id}};
  if (client_publish) info["supportedEncodings"] = json::array({"json"});
  return info.dump();
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

void RequireShallowJson(std::string_view text, int max_depth) {
  int depth = 0;
  bool in_string = false;
  bool escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        throw ProtocolError("JSON nested deeper than " + std::to_string(max_depth) + " levels");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

ClientOp ParseClientText(std::string_view text, std::size_t max_items) {
  RequireShallowJson(text, kMaxJsonDepth);
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
  } else if (*op == "advertise") {
    parsed.kind = ClientOp::kAdvertise;
    for (const json& c : RequireArray(frame, "channels", "advertise", max_items)) {
      if (!c.is_object()) throw ProtocolError("advertise: a channel that is not an object");
      parsed.channels.push_back({RequireId(c, "id", "advertise"), RequireString(c, "topic", "advertise"),
                                 RequireString(c, "encoding", "advertise"),
                                 c.contains("schemaName") ? RequireString(c, "schemaName", "advertise") : ""});
    }
  } else if (*op == "unadvertise") {
    parsed.kind = ClientOp::kUnadvertise;
    for (const json& id : RequireArray(frame, "channelIds", "unadvertise", max_items)) {
      parsed.ids.push_back(RequireId(json{{"id", id}}, "id", "unadvertise"));
    }
  } else {
    throw ProtocolError("op \"" + op->get<std::string>() +
                        "\" is not one this server takes (subscribe, unsubscribe, advertise, unadvertise)");
  }
  return parsed;
}

ClientMessage ParseClientBinary(std::string_view frame) {
  if (frame.empty() || static_cast<std::uint8_t>(frame[0]) != kMessageDataOpcode) {
    throw ProtocolError("binary opcode " + std::to_string(frame.empty() ? -1 : static_cast<std::uint8_t>(frame[0])) +
                        " is not one this server takes (0x01, client message data)");
  }
  if (frame.size() < 5)
    throw ProtocolError("client message data of " + std::to_string(frame.size()) + " bytes (at least 5)");
  std::uint32_t channel = 0;
  for (int i = 0; i < 4; ++i) channel |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(frame[1 + i])) << (8 * i);
  return ClientMessage{channel, frame.substr(5)};
}

}  // namespace edsp::web::foxglove
