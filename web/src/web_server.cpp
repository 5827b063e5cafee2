#include "edsp/web/web_server.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <deque>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include "edsp/channels.h"
#include "edsp/node/runtime.h"
#include "edsp/web/client_feed.h"
#include "edsp/web/drift_report_page.h"
#include "edsp/web/foxglove_protocol.h"
#include "edsp/web/http_access.h"
#include "edsp/web/message_json.h"

namespace edsp::web {
// Named, not anonymous: WebServer::Impl holds a Shared.
namespace web_server_internal {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using Request = http::request<http::string_body>;
// A connection's stream: plain TCP, or TLS over it (--tls-cert, --tls-key).
using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

// How much one client may make the server hold or do.
constexpr std::size_t kMaxQueuedFrames = 256;   // errors it does not read, plus one batch of due frames
constexpr std::size_t kMaxItemsPerOp = 256;     // subscriptions in one subscribe
constexpr std::size_t kMaxClientChannels = 16;  // channels one client advertises
constexpr std::int64_t kMaxClients = 64;
constexpr std::size_t kMaxRequestBytes = 8192;  // a panel's GET or an upgrade: headers only

// Where the panel's browser libraries are served from (WebServerOptions::javascript_dir).
constexpr std::string_view kJavascriptPrefix = "/javascript/";

// What an HTTP response carries besides its status.
struct Page {
  std::string body;
  const char* content_type;
};

// Beast's string_view is Boost's.
std::string_view View(beast::string_view text) { return {text.data(), text.size()}; }

std::int64_t SteadyNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::vector<foxglove::ServerChannel> AdvertisedChannels() {
  std::vector<foxglove::ServerChannel> channels;
  for (std::size_t i = 0; i < ChannelBoard::ChannelCount(); ++i) {
    const channel::Channel& c = channel::kChannels[i];
    channels.push_back(foxglove::ServerChannel{static_cast<std::uint32_t>(i + 1), std::string(c.name),
                                               "edsp." + std::string(c.type), MessageSchema(c.type)});
  }
  return channels;
}

struct Counters {
  std::atomic<std::int64_t> clients{0};
  std::atomic<std::int64_t> connections{0};
  std::atomic<std::int64_t> refused{0};
  std::atomic<std::int64_t> frames_sent{0};
  std::atomic<std::int64_t> protocol_errors{0};
  std::atomic<std::int64_t> stalled_clients{0};
  std::atomic<std::int64_t> requests{0};
};

// What every session reads (the io thread's alone, but for the counters).
struct Shared {
  ChannelBoard* board = nullptr;
  WebServerOptions options;
  std::string server_info_viewer;
  std::string server_info_operator;  // with clientPublish, when requests can be sent
  std::string advertise;
  Counters counters;
  LoginLimiter limiter{10, std::chrono::seconds(60)};
  std::unique_ptr<RequestRelay> relay;     // null: nobody publishes
  bool loopback_only = false;              // listening on loopback: Host must name it too
  std::unique_ptr<net::ssl::context> tls;  // null: plain HTTP and WebSocket
};

// The server's TLS context from a PEM certificate chain and its private
// key; throws std::runtime_error naming the file that cannot be used.
std::unique_ptr<net::ssl::context> TlsContext(const std::string& cert, const std::string& key) {
  if (cert.empty() || key.empty()) {
    throw std::runtime_error("TLS needs both a certificate (--tls-cert) and its key (--tls-key)");
  }
  auto context = std::make_unique<net::ssl::context>(net::ssl::context::tls_server);
  context->set_options(net::ssl::context::default_workarounds | net::ssl::context::no_sslv2 |
                       net::ssl::context::no_sslv3 | net::ssl::context::no_tlsv1 | net::ssl::context::no_tlsv1_1);
  beast::error_code error;
  context->use_certificate_chain_file(cert, error);
  if (error) {
    throw std::runtime_error("--tls-cert " + cert + ": not a readable PEM certificate chain (" + error.message() + ")");
  }
  // OpenSSL checks here that the key is the certificate's too.
  context->use_private_key_file(key, net::ssl::context::pem, error);
  if (error || SSL_CTX_check_private_key(context->native_handle()) != 1) {
    throw std::runtime_error("--tls-key " + key + ": not a readable PEM private key of the certificate in " + cert +
                             (error ? " (" + error.message() + ")" : std::string()));
  }
  return context;
}

// Who a connection is: a token's name and role, or a public viewer.
struct Identity {
  std::string name;
  Role role = Role::kViewer;
};

// One client's WebSocket: the protocol's session.
template <class Stream>
class WsSession : public std::enable_shared_from_this<WsSession<Stream>> {
 public:
  WsSession(Stream&& stream, std::shared_ptr<Shared> shared, Identity identity)
      : ws_(std::move(stream)),
        timer_(ws_.get_executor()),
        shared_(std::move(shared)),
        identity_(std::move(identity)),
        feed_(shared_->board, shared_->options.rate_cap_hz) {}

  ~WsSession() {
    if (open_) --shared_->counters.clients;
    if (shared_->relay) shared_->relay->ForgetOwner(reinterpret_cast<std::uintptr_t>(this));
  }

  void Start(Request request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
      response.set(http::field::sec_websocket_protocol, foxglove::kSubprotocol);
      response.set(http::field::server, "edsp-web");
    }));
    ws_.read_message_max(shared_->options.max_client_frame_bytes);
    ws_.async_accept(request, beast::bind_front_handler(&WsSession::OnAccept, this->shared_from_this()));
  }

 private:
  void OnAccept(beast::error_code error) {
    if (error) return;
    open_ = true;
    ++shared_->counters.clients;
    ++shared_->counters.connections;
    Queue(true, MayPublish() ? shared_->server_info_operator : shared_->server_info_viewer);
    Queue(true, shared_->advertise);
    WriteNext();
    Read();
    Tick();
  }

  void Read() { ws_.async_read(in_, beast::bind_front_handler(&WsSession::OnRead, this->shared_from_this())); }

  void OnRead(beast::error_code error, std::size_t) {
    if (error) {
      Close();
      return;
    }
    const bool text = ws_.got_text();
    const std::string frame = beast::buffers_to_string(in_.data());
    in_.consume(in_.size());
    Handle(text, frame);
    if (!closed_) Read();
  }

  // A client frame: its operation done, or an error status naming what is
  // wrong with it and nothing changed.
  void Handle(bool text, const std::string& frame) {
    try {
      if (!text) return Publish(foxglove::ParseClientBinary(frame));
      const foxglove::ClientOp op = foxglove::ParseClientText(frame, kMaxItemsPerOp);
      switch (op.kind) {
        case foxglove::ClientOp::kSubscribe:
          for (const foxglove::Subscription& s : op.subscriptions) feed_.Subscribe(s.id, s.channel_id);
          break;
        case foxglove::ClientOp::kUnsubscribe:
          for (std::uint32_t id : op.ids) feed_.Unsubscribe(id);
          break;
        case foxglove::ClientOp::kAdvertise:
          for (const foxglove::ClientChannel& c : op.channels) Advertised(c);
          break;
        case foxglove::ClientOp::kUnadvertise:
          for (std::uint32_t id : op.ids) {
            if (client_channels_.erase(id) == 0) {
              throw foxglove::ProtocolError("unadvertise: no client channel " + std::to_string(id));
            }
          }
          break;
      }
    } catch (const foxglove::ProtocolError& e) {
      ++shared_->counters.protocol_errors;
      Queue(true, foxglove::Status(foxglove::kError, e.what()));
      WriteNext();
    } catch (const std::exception& e) {  // the bus refused a request: said, and the server goes on
      ++shared_->counters.protocol_errors;
      Queue(true, foxglove::Status(foxglove::kError, std::string("not done: ") + e.what()));
      WriteNext();
    }
  }

  bool MayPublish() const { return identity_.role == Role::kOperator && shared_->relay != nullptr; }

  void RequirePublisher(const char* what) const {
    if (MayPublish()) return;
    throw foxglove::ProtocolError(std::string(what) + ": " +
                                  (shared_->relay == nullptr
                                       ? std::string("this server relays no requests")
                                       : identity_.name + " is a viewer; requests need an operator's token"));
  }

  void Advertised(const foxglove::ClientChannel& c) {
    RequirePublisher("advertise");
    if (!IsRequestChannel(c.topic)) {
      throw foxglove::ProtocolError(
          "advertise: " + c.topic +
          " is not a request channel (EDSP_MOTION_REQUEST, EDSP_ARM, EDSP_PR_MODE, EDSP_CALIBRATION)");
    }
    if (c.encoding != "json") throw foxglove::ProtocolError("advertise: " + c.topic + ": encoding must be json");
    if (client_channels_.size() >= kMaxClientChannels && client_channels_.count(c.id) == 0) {
      throw foxglove::ProtocolError("advertise: at most " + std::to_string(kMaxClientChannels) + " client channels");
    }
    client_channels_[c.id] = c.topic;
  }

  // An operator's request: on the bus through the relay, at most
  // max_requests_per_s a second from this client.
  void Publish(const foxglove::ClientMessage& m) {
    RequirePublisher("client message data");
    const auto channel = client_channels_.find(m.channel_id);
    if (channel == client_channels_.end()) {
      throw foxglove::ProtocolError("client message data on channel " + std::to_string(m.channel_id) +
                                    ", which this client did not advertise");
    }
    const auto now = std::chrono::steady_clock::now();
    while (!recent_requests_.empty() && now - recent_requests_.front() > std::chrono::seconds(1)) {
      recent_requests_.pop_front();
    }
    if (static_cast<double>(recent_requests_.size()) >= shared_->options.max_requests_per_s) {
      throw foxglove::ProtocolError(channel->second + ": more than " +
                                    std::to_string(static_cast<int>(shared_->options.max_requests_per_s)) +
                                    " requests a second; this one was not sent");
    }
    recent_requests_.push_back(now);
    shared_->relay->Submit(channel->second, m.payload, "web:" + identity_.name, SteadyNs(), UtimeNow(),
                           reinterpret_cast<std::uintptr_t>(this));
    ++shared_->counters.requests;
  }

  void Tick() {
    timer_.expires_after(shared_->options.tick);
    timer_.async_wait([self = this->shared_from_this()](beast::error_code error) {
      if (error || self->closed_) return;
      self->OnTick();
      if (!self->closed_) self->Tick();
    });
  }

  // Due frames only when the socket has taken the last ones: a slow client
  // gets the newest, not a backlog; one that takes nothing is let go.
  void OnTick() {
    if (writing_) {
      if (std::chrono::steady_clock::now() - write_started_ > shared_->options.stall_timeout) {
        ++shared_->counters.stalled_clients;
        Close();
      }
      return;
    }
    const std::size_t room = kMaxQueuedFrames / 2 - std::min(queue_.size(), kMaxQueuedFrames / 2);
    for (const FeedFrame& f : feed_.Due(SteadyNs(), room)) {
      Queue(false, foxglove::MessageData(f.subscription_id, static_cast<std::uint64_t>(f.receive_ns), *f.json));
      ++shared_->counters.frames_sent;
    }
    WriteNext();
  }

  void Queue(bool text, std::string data) {
    if (queue_.size() >= kMaxQueuedFrames) {  // it sends and does not read: it goes
      Close();
      return;
    }
    queue_.push_back(Outgoing{text, std::move(data)});
  }

  void WriteNext() {
    if (writing_ || queue_.empty() || closed_) return;
    writing_ = true;
    write_started_ = std::chrono::steady_clock::now();
    ws_.text(queue_.front().text);
    ws_.async_write(net::buffer(queue_.front().data),
                    beast::bind_front_handler(&WsSession::OnWrite, this->shared_from_this()));
  }

  void OnWrite(beast::error_code error, std::size_t) {
    writing_ = false;
    if (error) {
      Close();
      return;
    }
    queue_.pop_front();
    WriteNext();
  }

  void Close() {
    if (closed_) return;
    closed_ = true;
    timer_.cancel();
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(ws_).socket().close(ignored);
  }

  struct Outgoing {
    bool text = true;
    std::string data;
  };

  websocket::stream<Stream> ws_;
  net::steady_timer timer_;
  std::shared_ptr<Shared> shared_;
  Identity identity_;
  ClientFeed feed_;
  std::map<std::uint32_t, std::string> client_channels_;  // advertised by the client: id -> request channel
  std::deque<std::chrono::steady_clock::time_point> recent_requests_;
  beast::flat_buffer in_;
  std::deque<Outgoing> queue_;
  bool writing_ = false;
  bool open_ = false;
  bool closed_ = false;
  std::chrono::steady_clock::time_point write_started_;
};

// One HTTP connection: its TLS handshake where it has one, who it is, then
// a static file or the upgrade to a WebSocket session.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
 public:
  static constexpr bool kTls = std::is_same_v<Stream, TlsStream>;

  template <class... StreamArgs>
  explicit HttpSession(std::shared_ptr<Shared> shared, StreamArgs&&... stream_args)
      : stream_(std::forward<StreamArgs>(stream_args)...), shared_(std::move(shared)) {}

  void Start() {
    if constexpr (kTls) {
      beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(30));
      stream_.async_handshake(net::ssl::stream_base::server,
                              [self = this->shared_from_this()](beast::error_code error) {
                                if (!error)
                                  self->Read();  // not TLS, or a certificate the client refused: nothing to answer
                              });
    } else {
      Read();
    }
  }

  void Read() {
    parser_.emplace();
    parser_->header_limit(kMaxRequestBytes);
    parser_->body_limit(kMaxRequestBytes);
    beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&HttpSession::OnRead, this->shared_from_this()));
  }

 private:
  void OnRead(beast::error_code error, std::size_t) {
    if (error == http::error::end_of_stream) return Shutdown();
    if (error) {
      if (error == http::error::header_limit || error == http::error::body_limit) {
        return Respond(
            http::status::payload_too_large,
            Page{"request larger than " + std::to_string(kMaxRequestBytes) + " bytes\n", "text/plain; charset=utf-8"},
            11, false);
      }
      return;
    }
    Route(parser_->release());
  }

  void Route(Request request) {
    if (shared_->loopback_only && !LoopbackHost(View(request[http::field::host]))) {
      return Refuse(http::status::forbidden,
                    "Host " + std::string(View(request[http::field::host])) +
                        " is not this host's loopback, where this server listens (--bind opens it to a network)",
                    request);
    }
    const std::string_view path = TargetPath(View(request.target()));
    if (websocket::is_upgrade(request) || PathNeedsToken(path)) {
      std::optional<Identity> identity = Authorize(request);
      if (!identity) return;
      if (websocket::is_upgrade(request)) return Upgrade(std::move(request), std::move(*identity));
    }
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
      return Refuse(http::status::method_not_allowed, "only GET and HEAD are served", request);
    }
    if (path == kDriftReportPath) return ServeDriftReport(request);
    std::optional<Page> page =
        path.substr(0, kJavascriptPrefix.size()) == kJavascriptPrefix
            ? FilePage(shared_->options.javascript_dir, path.substr(kJavascriptPrefix.size() - 1))
            : FilePage(shared_->options.panel_dir, path);
    if (!page) return Refuse(http::status::not_found, "no such page: " + std::string(path), request);
    Respond(http::status::ok, std::move(*page), request.version(), request.keep_alive(),
            request.method() == http::verb::head);
  }

  void ServeDriftReport(const Request& request) {
    DriftReportAnswer answer = DriftReportPage(shared_->options.drift_report);
    const bool ok = answer.http_status == 200;
    Respond(
        static_cast<http::status>(answer.http_status),
        Page{ok ? std::move(answer.body) : answer.body + "\n", ok ? "application/json" : "text/plain; charset=utf-8"},
        request.version(), request.keep_alive(), request.method() == http::verb::head);
  }

  static std::optional<Page> FilePage(const std::string& root, std::string_view path) {
    const std::optional<std::string> file = StaticFile(root, path);
    std::ifstream in;
    if (file) in.open(*file, std::ios::binary);
    if (!file || !in.is_open()) return std::nullopt;
    std::ostringstream body;
    body << in.rdbuf();
    return Page{body.str(), ContentType(*file)};
  }

  // Who the request's token says it is (a public viewer without one under
  // --public-view); none, with the refusal sent, otherwise.
  std::optional<Identity> Authorize(const Request& request) {
    const auto now = std::chrono::steady_clock::now();
    beast::error_code ignored;
    const std::string address =
        beast::get_lowest_layer(stream_).socket().remote_endpoint(ignored).address().to_string();
    if (shared_->limiter.Blocked(address, now)) {
      Refuse(http::status::too_many_requests, "too many wrong tokens from " + address + "; try again in a minute",
             request);
      return std::nullopt;
    }
    const std::optional<std::string> token =
        PresentedToken(View(request.target()), View(request[http::field::authorization]));
    if (!token) {
      if (shared_->options.public_view) return Identity{"public", Role::kViewer};
      Refuse(http::status::unauthorized, "a token is needed: ?token=T on the URL or Authorization: Bearer T", request);
      return std::nullopt;
    }
    const std::optional<TokenEntry> entry = shared_->options.tokens.Check(*token);
    if (!entry) {
      shared_->limiter.Failed(address, now);
      Refuse(http::status::unauthorized, "unknown token", request);
      return std::nullopt;
    }
    return Identity{entry->name, entry->role};
  }

  void Upgrade(Request request, Identity identity) {
    const std::string_view origin = View(request[http::field::origin]);
    if (!OriginAllowed(origin, View(request[http::field::host]), shared_->options.allowed_origins)) {
      return Refuse(http::status::forbidden,
                    "Origin " + std::string(origin) + " is not this server's (edsp-web --allow-origin adds one)",
                    request);
    }
    const std::string_view offered = View(request[http::field::sec_websocket_protocol]);
    if (offered.find(foxglove::kSubprotocol) == std::string_view::npos) {
      return Refuse(http::status::bad_request,
                    std::string("the WebSocket subprotocol must be ") + foxglove::kSubprotocol, request);
    }
    if (shared_->counters.clients >= kMaxClients) {
      return Refuse(http::status::service_unavailable, "already " + std::to_string(kMaxClients) + " clients", request);
    }
    beast::get_lowest_layer(stream_).expires_never();
    std::make_shared<WsSession<Stream>>(std::move(stream_), shared_, std::move(identity))->Start(std::move(request));
  }

  void Refuse(http::status status, const std::string& reason, const Request& request) {
    ++shared_->counters.refused;
    Respond(status, Page{reason + "\n", "text/plain; charset=utf-8"}, request.version(), false,
            request.method() == http::verb::head);
  }

  void Respond(http::status status, Page page, unsigned version, bool keep_alive, bool head = false) {
    auto response = std::make_shared<http::response<http::string_body>>(status, version);
    response->set(http::field::server, "edsp-web");
    response->set(http::field::content_type, page.content_type);
    response->set(http::field::cache_control, "no-store");
    if (status == http::status::unauthorized) response->set(http::field::www_authenticate, "Bearer");
    response->keep_alive(keep_alive);
    response->body() = std::move(page.body);
    response->prepare_payload();
    if (head) response->body().clear();
    http::async_write(stream_, *response,
                      [self = this->shared_from_this(), response, keep_alive](beast::error_code error, std::size_t) {
                        if (error) return;
                        if (keep_alive) return self->Read();
                        self->Shutdown();
                      });
  }

  void Shutdown() {
    if constexpr (kTls) {
      beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(5));
      stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {});
    } else {
      beast::error_code ignored;
      stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    }
  }

  Stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<Shared> shared_;
};

}  // namespace web_server_internal

namespace net = boost::asio;
namespace beast = boost::beast;
using web_server_internal::Counters;
using web_server_internal::HttpSession;
using web_server_internal::PlainStream;
using web_server_internal::Shared;
using web_server_internal::TlsStream;
using tcp = net::ip::tcp;

struct WebServer::Impl {
  net::io_context io{1};
  tcp::acceptor acceptor{io};
  net::steady_timer relay_timer{io};
  std::shared_ptr<Shared> shared = std::make_shared<Shared>();

  // Requests sent again until answered, every 50 ms looked at.
  void TickRelay() {
    relay_timer.expires_after(std::chrono::milliseconds(50));
    relay_timer.async_wait([this](beast::error_code error) {
      if (error) return;
      try {
        shared->relay->Tick(web_server_internal::SteadyNs());
      } catch (const std::exception& e) {  // a resend the bus refused: the next tick tries again
        std::fprintf(stderr, "edsp-web: a request could not be sent again: %s\n", e.what());
      }
      TickRelay();
    });
  }

  void Accept() {
    acceptor.async_accept([this](beast::error_code error, tcp::socket socket) {
      if (error == net::error::operation_aborted) return;
      if (!error && shared->tls) {
        std::make_shared<HttpSession<TlsStream>>(shared, std::move(socket), *shared->tls)->Start();
      } else if (!error) {
        std::make_shared<HttpSession<PlainStream>>(shared, std::move(socket))->Start();
      }
      Accept();
    });
  }
};

WebServer::WebServer(ChannelBoard* board, WebServerOptions options) : impl_(std::make_unique<Impl>()) {
  Shared& shared = *impl_->shared;
  shared.board = board;
  shared.options = std::move(options);
  const std::string session = std::to_string(shared.options.session_id);
  shared.server_info_viewer = foxglove::ServerInfo(shared.options.name, session, shared.options.metadata, false);
  shared.server_info_operator =
      foxglove::ServerInfo(shared.options.name, session, shared.options.metadata, shared.options.publish != nullptr);
  if (shared.options.publish) {
    shared.relay = std::make_unique<RequestRelay>(board, shared.options.publish, shared.options.session_id);
  }
  shared.advertise = foxglove::Advertise(web_server_internal::AdvertisedChannels());
  if (!shared.options.tls_cert.empty() || !shared.options.tls_key.empty()) {
    shared.tls = web_server_internal::TlsContext(shared.options.tls_cert, shared.options.tls_key);
  }
  const std::string where = shared.options.bind + ":" + std::to_string(shared.options.port);
  beast::error_code error;
  const net::ip::address address = net::ip::make_address(shared.options.bind, error);
  if (error) throw std::runtime_error("--bind " + shared.options.bind + ": not an IP address");
  const tcp::endpoint endpoint(address, shared.options.port);
  shared.loopback_only = address.is_loopback();
  impl_->acceptor.open(endpoint.protocol(), error);
  if (!error) impl_->acceptor.set_option(net::socket_base::reuse_address(true), error);
  if (!error) impl_->acceptor.bind(endpoint, error);
  if (!error) impl_->acceptor.listen(net::socket_base::max_listen_connections, error);
  if (error) throw std::runtime_error("cannot listen on " + where + ": " + error.message());
  impl_->Accept();
  if (impl_->shared->relay) impl_->TickRelay();
}

WebServer::~WebServer() = default;

std::uint16_t WebServer::port() const { return impl_->acceptor.local_endpoint().port(); }

void WebServer::Run(const std::function<bool()>& stop, std::chrono::milliseconds poll) {
  while (!stop()) {
    impl_->io.run_for(poll);
    if (impl_->io.stopped()) impl_->io.restart();
  }
}

WebServerStats WebServer::stats() const {
  const Counters& c = impl_->shared->counters;
  return WebServerStats{c.clients,         c.connections,     c.refused, c.frames_sent,
                        c.protocol_errors, c.stalled_clients, c.requests};
}

}  // namespace edsp::web
