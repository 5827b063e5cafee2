#pragma once
// edsp-web as a node of its group: the group's channels read into a
// ChannelBoard (BoardFeeder), served by the WebServer, operators' requests
// published on the group's bus, and EDSP_STATUS once a second as every node
// reports it (messages in from the bus, frames out to clients, requests and
// frames refused). Its run is the server's own loop: Asio waits on the
// sockets, the bus is read on the feeder's thread.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "edsp/node/node_options.h"
#include "edsp/web/web_server.h"

namespace edsp::web {

class WebNode {
 public:
  // Loads the tokens (throws std::runtime_error when there is none and the
  // view is not public: nobody could connect), opens the bus and binds the
  // port. `session_given`: the group's session is known (a member of it);
  // beside a group, the planner's status says it.
  WebNode(const NodeOptions& node, bool session_given, WebServerOptions options, const std::string& tokens_path);
  ~WebNode();
  WebNode(const WebNode&) = delete;
  WebNode& operator=(const WebNode&) = delete;

  std::uint16_t port() const;
  // Serves until stop() is true; throws std::runtime_error when the bus failed.
  void Run(const std::function<bool()>& stop);

 private:
  struct Parts;
  std::unique_ptr<Parts> parts_;
};

}  // namespace edsp::web
