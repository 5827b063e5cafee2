#include "edsp/web/web_node.h"

#include <stdexcept>
#include <utility>
#include <variant>

#include <nlohmann/json.hpp>

#include "edsp/node/node_reporting.h"
#include "edsp/node/runtime.h"
#include "edsp/request_kinds.h"
#include "edsp/transport/bus.h"
#include "edsp/web/board_feeder.h"
#include "edsp/web/channel_board.h"
#include "edsp/web/token_store.h"

namespace edsp::web {

namespace {

// EDSP_STATUS from the server's and the board's counters, once a second.
class WebStatus {
 public:
  WebStatus(Bus* bus, const ChannelBoard* board, const WebServer* server)
      : reporting_(*bus, "web"), board_(board), server_(server) {
    reporting_.status().SetState(node_status_t::STATE_RUNNING);
  }
  void Tick() {
    const WebServerStats now = server_->stats();
    const auto posted = static_cast<std::int64_t>(board_->posted());
    reporting_.status().CountIn(posted - posted_);
    reporting_.status().CountOut(now.frames_sent - last_.frames_sent);
    for (std::int64_t i = Refusals(last_); i < Refusals(now); ++i) reporting_.status().CountRejected();
    posted_ = posted;
    last_ = now;
    reporting_.StatusTick(UtimeNow(), 0);
  }

 private:
  static std::int64_t Refusals(const WebServerStats& s) { return s.refused + s.protocol_errors; }
  NodeReporting reporting_;
  const ChannelBoard* board_;
  const WebServer* server_;
  WebServerStats last_{};
  std::int64_t posted_ = 0;
};

// The motion request kinds by name ({"move": 1, …}, request_kinds.h) as one
// metadata string (the protocol's metadata maps strings to strings): the
// panel takes its kinds from it, never from numbers of its own.
std::string RequestKindsJson() {
  nlohmann::json kinds = nlohmann::json::object();
  for (const RequestKindRow& row : kRequestKinds) kinds[std::string(row.name)] = row.kind;
  return kinds.dump();
}

WebServerOptions Completed(const NodeOptions& node, bool session_given, WebServerOptions options,
                           const std::string& tokens_path) {
  options.tokens = TokenStore::Load(tokens_path);
  if (options.tokens.entries().empty() && !options.public_view) {
    throw std::runtime_error(tokens_path +
                             " has no token, so nobody could connect: add one with `edsp-web token add NAME --role "
                             "operator`, or serve --public-view");
  }
  options.session_id = session_given ? node.session_id : 0;
  options.metadata = {{"group", node.group_path}, {"request_kinds", RequestKindsJson()}};
  // The panel looks for a drift report only where there is one to read
  // (said, not where: the path is the server's business).
  if (!options.drift_report.empty()) options.metadata["drift_report"] = "true";
  return options;
}

}  // namespace

// In the order they are built and the reverse of their end: the feeder
// writes the board, the server reads it and publishes on `requests`.
struct WebNode::Parts {
  Parts(const NodeOptions& node, WebServerOptions options)
      : feeder(TransportFor(node), &board),
        requests(TransportFor(node)),
        server(&board, WithPublish(options)),
        status(&requests, &board, &server) {}

  // Operators' requests go out on `requests`, from the server's thread alone.
  WebServerOptions WithPublish(WebServerOptions options) {
    options.publish = [this](const std::string& channel, const RequestMessage& request) {
      return std::visit([&](const auto& m) { return requests.Publish(channel, m); }, request);
    };
    return options;
  }

  ChannelBoard board;
  BoardFeeder feeder;
  Bus requests;
  WebServer server;
  WebStatus status;
};

WebNode::WebNode(const NodeOptions& node, bool session_given, WebServerOptions options, const std::string& tokens_path)
    : parts_(std::make_unique<Parts>(node, Completed(node, session_given, std::move(options), tokens_path))) {}

WebNode::~WebNode() = default;

std::uint16_t WebNode::port() const { return parts_->server.port(); }

void WebNode::Run(const std::function<bool()>& stop) {
  Parts& p = *parts_;
  p.server.Run([&] {
    p.status.Tick();
    return stop() || !p.feeder.error().empty();
  });
  p.feeder.Stop();
  if (!p.feeder.error().empty()) throw std::runtime_error("the bus failed: " + p.feeder.error());
}

}  // namespace edsp::web
