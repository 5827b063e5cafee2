#pragma once
// The foxglove.websocket.v1 protocol (github.com/foxglove/ws-protocol,
// docs/spec.md), the part edsp-web speaks: what the server sends (server
// info, status, advertise, message data) and what a client may send
// (subscribe, unsubscribe; an operator's client also advertise,
// unadvertise and client message data, its requests). Lichtblick and Foxglove read edsp's channels
// through it without configuration; edsp's own panel speaks it too.
// Every client frame is untrusted: a parse either yields a well-formed
// operation or throws ProtocolError saying what is wrong with it.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace edsp::web::foxglove {

inline constexpr char kSubprotocol[] = "foxglove.websocket.v1";
inline constexpr std::uint8_t kMessageDataOpcode = 0x01;
inline constexpr int kMaxJsonDepth = 16;  // deeper than any frame or request of edsp's
enum StatusLevel { kInfo = 0, kWarning = 1, kError = 2 };

class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A channel the server advertises: JSON messages, a JSON schema.
struct ServerChannel {
  std::uint32_t id = 0;
  std::string topic;
  std::string schema_name;
  nlohmann::ordered_json schema;
};

// With `client_publish`, the capability "clientPublish" and the one
// encoding it takes, "json".
std::string ServerInfo(std::string_view name, std::string_view session_id, const nlohmann::json& metadata,
                       bool client_publish);
std::string Status(StatusLevel level, std::string_view message);
std::string Advertise(const std::vector<ServerChannel>& channels);
// Binary: opcode, subscription id (u32 LE), receive time (u64 LE, ns), payload.
std::string MessageData(std::uint32_t subscription_id, std::uint64_t receive_ns, std::string_view payload);

struct Subscription {
  std::uint32_t id = 0;
  std::uint32_t channel_id = 0;
};

// A channel a client advertises to publish on.
struct ClientChannel {
  std::uint32_t id = 0;
  std::string topic;
  std::string encoding;
  std::string schema_name;
};

struct ClientOp {
  enum Kind { kSubscribe, kUnsubscribe, kAdvertise, kUnadvertise } kind = kSubscribe;
  std::vector<Subscription> subscriptions;  // kSubscribe
  std::vector<std::uint32_t> ids;           // kUnsubscribe (subscriptions), kUnadvertise (channels)
  std::vector<ClientChannel> channels;      // kAdvertise
};

// A client's binary frame: client message data (opcode 0x01, channel id
// u32 LE, payload). The payload views `frame`.
struct ClientMessage {
  std::uint32_t channel_id = 0;
  std::string_view payload;
};

// Throws ProtocolError if `text` nests arrays and objects deeper than
// `max_depth` (JSON's own parsers recurse on copies and dumps: a 64 KiB
// frame of brackets must not reach them).
void RequireShallowJson(std::string_view text, int max_depth);

// A client's text frame. At most `max_items` subscriptions, ids or channels
// in one (a frame is bounded by the server's message size, this by its
// work). Throws ProtocolError naming the op, field or value at fault: not
// JSON, no "op", an op this server does not take, a missing or non-u32 id,
// a channel without a string topic or encoding.
ClientOp ParseClientText(std::string_view text, std::size_t max_items);
// Throws ProtocolError for another opcode or a frame shorter than its header.
ClientMessage ParseClientBinary(std::string_view frame);

}  // namespace edsp::web::foxglove
