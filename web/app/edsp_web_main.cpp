// edsp-web: the rig's operator panel and its WebSocket protocol on one port.
//   edsp-web [--group FILE] [--port 8765] [--bind ADDR] [--tokens FILE] [--public-view]
//            [--tls-cert C --tls-key K] [--allow-origin ORIGIN]... [--panel DIR] [--rate-hz 30]
//   edsp-web token add NAME --role viewer|operator [--tokens FILE]   (prints the new token once)
//   edsp-web token list [--tokens FILE]
//   edsp-web token revoke NAME [--tokens FILE]
// It reads every EDSP_* channel of the group (--group, as a member or beside
// a running group) and serves them as foxglove.websocket.v1 (JSON messages
// with the .lcm field names, a JSON schema each), latest-wins at --rate-hz
// per client for the cyclic channels, every message for faults and replies;
// an operator's client may publish requests (EDSP_MOTION_REQUEST, EDSP_ARM,
// EDSP_PR_MODE, EDSP_CALIBRATION), stamped with the group's session and
// "web:NAME", which the nodes check as they check edsp-ctl's.
// Localhost only unless --bind says otherwise; every client presents a
// token (?token=T or Authorization: Bearer T) unless --public-view.
#include <cstdio>
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>

#include "edsp/node/build_paths.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/web/token_commands.h"
#include "edsp/web/token_store.h"
#include "edsp/web/web_node.h"
#include "edsp/web/web_server.h"

namespace edsp {
namespace {

// The panel beside an installed edsp-web (<prefix>/share/edsp/panel), else
// this build's checkout's.
std::string DefaultPanelDir() {
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share/edsp/panel";
    if (std::filesystem::is_regular_file(installed / "index.html", error)) return installed.string();
  }
  return SourcePath("web/panel");
}

int Serve(const NodeOptions& node, bool session_given, const web::WebServerOptions& options,
          const std::string& tokens_path) {
  web::WebNode web(node, session_given, options, tokens_path);
  std::fprintf(stderr, "edsp-web: serving %s on %s://%s:%u (panel %s)\n",
               node.group_path.empty() ? "the default bus" : node.group_path.c_str(),
               options.tls_cert.empty() ? "http" : "https", options.bind.c_str(), static_cast<unsigned>(web.port()),
               options.panel_dir.c_str());
  InstallStopSignals();
  web.Run(StopRequested);
  return 0;
}

int Run(int argc, char** argv) {
  NodeApp app{"edsp-web: the rig's panel and its WebSocket protocol (foxglove.websocket.v1)"};
  web::WebServerOptions options;
  options.panel_dir = DefaultPanelDir();
  std::string tokens_path = web::DefaultTokensPath();
  app.add_option("--port", options.port, "TCP port (0: any free one)");
  app.add_option("--bind", options.bind, "address to listen on (default localhost only)");
  app.add_option("--tokens", tokens_path, "tokens file (hashes only, mode 0600)");
  app.add_flag("--public-view", options.public_view, "viewers need no token");
  CLI::Option* cert = app.add_option("--tls-cert", options.tls_cert, "TLS: PEM certificate chain (https, wss)")
                          ->check(CLI::ExistingFile);
  CLI::Option* key =
      app.add_option("--tls-key", options.tls_key, "TLS: the certificate's PEM private key")->check(CLI::ExistingFile);
  cert->needs(key);
  key->needs(cert);
  app.add_option("--allow-origin", options.allowed_origins, "a browser Origin allowed besides the served host");
  app.add_option("--panel", options.panel_dir, "the panel's static files")->check(CLI::ExistingDirectory);
  app.add_option("--drift-report", options.drift_report,
                 "edsp-gap drift --json's output, shown in the panel's calibration view (read at each look)");
  app.add_option("--rate-hz", options.rate_cap_hz, "most frames per second of a cyclic channel, per client")
      ->check(CLI::Range(0.1, 1000.0));

  CLI::App* token = app.add_subcommand("token", "manage the tokens file")->require_subcommand(1);
  std::string name;
  std::string role;
  CLI::App* add = token->add_subcommand("add", "a new token for NAME; prints it once");
  add->add_option("name", name, "who it is for")->required();
  add->add_option("--role", role, "viewer or operator")->required()->check(CLI::IsMember({"viewer", "operator"}));
  CLI::App* list = token->add_subcommand("list", "names and roles");
  CLI::App* revoke = token->add_subcommand("revoke", "remove NAME's token");
  revoke->add_option("name", name, "whose token")->required();
  for (CLI::App* sub : {add, list, revoke}) sub->add_option("--tokens", tokens_path, "tokens file");
  CLI11_PARSE(app, argc, argv);

  if (add->parsed()) web::AddToken(tokens_path, name, role);
  if (list->parsed()) web::ListTokens(tokens_path);
  if (revoke->parsed()) web::RevokeToken(tokens_path, name);
  if (token->parsed()) return 0;
  return Serve(app.node, app.count("--session-id") > 0, options, tokens_path);
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-web", edsp::Run, argc, argv); }
