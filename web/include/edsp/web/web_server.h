#pragma once
// edsp-web's HTTP and WebSocket server (Boost.Beast, one thread): the
// panel's static files and the foxglove.websocket.v1 protocol on one port.
// Every client is fed from the ChannelBoard by its own ClientFeed whenever
// its socket has taken the last frame, so a slow client gets fewer, newer
// frames, holds one frame in flight, and never slows the others or the bus;
// one that takes nothing for `stall_timeout` is disconnected. An operator's
// client may also publish requests (request_relay.h); a viewer's may not.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "edsp/web/channel_board.h"
#include "edsp/web/request_relay.h"
#include "edsp/web/token_store.h"

namespace edsp::web {

struct WebServerOptions {
  std::string bind = "127.0.0.1";  // localhost unless told otherwise (--bind)
  // TLS (https, wss) with this PEM certificate chain and private key; both
  // empty: plain HTTP and WebSocket.
  std::string tls_cert;
  std::string tls_key;
  std::uint16_t port = 8765;  // 0: any free port (tests)
  std::string panel_dir;      // the panel's static files
  // Debian's browser libraries (libjs-*), served under /javascript/ as
  // their own pages link them (/javascript/three/three.min.js).
  std::string javascript_dir = "/usr/share/javascript";
  TokenStore tokens;
  bool public_view = false;  // viewers need no token
  std::vector<std::string> allowed_origins;
  double rate_cap_hz = 30.0;  // per client and latest-wins channel
  std::size_t max_client_frame_bytes = 64 * 1024;
  std::chrono::milliseconds stall_timeout{10000};
  std::chrono::milliseconds tick{5};  // how often a client's due frames are looked for
  std::string name = "edsp-web";
  std::int64_t session_id = 0;  // the group's: serverInfo's, and every request's
  nlohmann::json metadata;      // serverInfo's
  // How an operator's request reaches the bus (request_relay.h); none: no
  // client publishes, whatever its role.
  RequestRelay::Publish publish;
  double max_requests_per_s = 20.0;  // per client
  // `edsp-gap drift --json`'s output, served at /drift-report.json for the
  // panel's calibration view (drift_report_page.h); empty: none.
  std::string drift_report;
};

struct WebServerStats {
  std::int64_t clients = 0;          // connected now
  std::int64_t connections = 0;      // WebSocket sessions opened in all
  std::int64_t refused = 0;          // requests refused (token, origin, limit)
  std::int64_t frames_sent = 0;      // message data frames
  std::int64_t protocol_errors = 0;  // client frames answered with an error status
  std::int64_t requests = 0;         // operators' requests relayed to the bus
  std::int64_t stalled_clients = 0;  // disconnected for taking nothing
};

class WebServer {
 public:
  // Binds at once; throws std::runtime_error naming the address and port.
  WebServer(ChannelBoard* board, WebServerOptions options);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  std::uint16_t port() const;
  // Serves until stop() returns true (asked every `poll`).
  void Run(const std::function<bool()>& stop, std::chrono::milliseconds poll = std::chrono::milliseconds(50));
  WebServerStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace edsp::web
