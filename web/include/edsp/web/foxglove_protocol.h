#pragma once
// The foxglove.websocket.v1 protocol (github.com/foxglove/ws-protocol,
// docs/spec.md), the part edsp-web speaks: what the server sends (server
// info, status, advertise, message data) and what a client may send
// (subscribe, unsubscribe). Lichtblick and Foxglove read edsp's channels
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

std::string ServerInfo(std::string_view name, std::string_view session_id, const nlohmann::json& metadata);
std::string Status(StatusLevel level, std::string_view message);
std::string Advertise(const std::vector<ServerChannel>& channels);
// Binary: opcode, subscription id (u32 LE), receive time (u64 LE, ns), payload.
std::string MessageData(std::uint32_t subscription_id, std::uint64_t receive_ns, std::string_view payload);

struct Subscription {
  std::uint32_t id = 0;
  std::uint32_t channel_id = 0;
};

struct ClientOp {
  enum Kind { kSubscribe, kUnsubscribe } kind = kSubscribe;
  std::vector<Subscription> subscriptions;  // kSubscribe
  std::vector<std::uint32_t> ids;           // kUnsubscribe
};

// A client's text frame. At most `max_items` subscriptions or ids in one
// (a frame is bounded by the server's message size, this by its work).
// Throws ProtocolError naming the op, field or value at fault: not JSON, no
// "op", an op this server does not take, a missing or non-u32 id.
ClientOp ParseClientText(std::string_view text, std::size_t max_items);

}  // namespace edsp::web::foxglove
